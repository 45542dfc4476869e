// An energy term of the user's own: a bar resting on nonlinear springs (each bottom vertex hangs
// from an anchor a distance h below it, E = k/2 (|x_v - a_v| - h)^2). The term passes tailor's
// derivative check, then joins a study that recovers the bar's Young's modulus from observations.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <vector>

#include "adjoint/derivative_check.hpp"
#include "problems/fem/study.hpp"

using namespace tailor;

class FoundationSprings final : public EnergyTerm {
 public:
  FoundationSprings(std::vector<int> vertices, const Vector& rest, double stiffness, double length)
      : vertices_(std::move(vertices)), k_(stiffness), h_(length) {
    for (int v : vertices_) anchors_.push_back(rest.segment<3>(3 * v) - Eigen::Vector3d(0, 0, h_));
  }
  std::string name() const override { return "foundation_springs"; }
  void hessian_pattern(HessianPattern& pattern) const override {
    for (int v : vertices_)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) pattern.push_back({3 * v + i, 3 * v + j});
  }
  void evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const override {
    for (std::size_t s = 0; s < vertices_.size(); ++s) {
      const int v = vertices_[s];
      const Eigen::Vector3d d = x.segment<3>(3 * v) - anchors_[s];
      const double r = d.norm();
      const Eigen::Vector3d n = d / r;
      if (request.value) *request.value += 0.5 * k_ * (r - h_) * (r - h_);
      if (request.gradient) request.gradient->segment<3>(3 * v) += k_ * (r - h_) * n;
      if (request.hessian_values) {
        // k (n n^T + (1 - h/r) (I - n n^T)); projected: the second part only where stretched.
        double lateral = 1.0 - h_ / r;
        if (request.hessian_mode == HessianMode::projected) lateral = std::max(lateral, 0.0);
        const Eigen::Matrix3d H =
            k_ * (n * n.transpose() + lateral * (Eigen::Matrix3d::Identity() - n * n.transpose()));
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(request.hessian_values + 9 * s) = H;
      }
    }
  }

 private:
  std::vector<int> vertices_;
  std::vector<Eigen::Vector3d> anchors_;
  double k_, h_;
};

int main() {
  Study study;
  study.mesh_box({0, 0, 0}, {4, 1, 1}, {8, 2, 2})
      .material(select::all(), "neo_hookean", 3e4, 0.3)
      .fix(select::plane("x", 0))
      .traction(select::plane("z", 1), {0, 0, -2e3})
      .energy([](const StaticSetup& setup) {
        std::vector<int> bottom;
        for (int v = 0; v < setup.mesh.num_vertices(); ++v)
          if (setup.mesh.rest_positions(v, 2) == 0.0) bottom.push_back(v);
        return std::make_unique<FoundationSprings>(bottom, setup.rest_state(), 1e4, 0.5);
      })
      .design({{"parameter", "youngs_modulus"}, {"granularity", "per_material"}, {"min", 1e3}, {"max", 1e7}})
      .objective(
          {{"type", "synthetic_observations"}, {"vertices", select::boundary()}, {"youngs_modulus", 1e5}})
      .optimizer({{"backend", "nlopt_lbfgs"}, {"gradient_tolerance", 1e-12}});

  // Every energy term of the model, the springs included, against central differences.
  bool checked = true;
  for (const EnergyTermCheck& check : study.check_energy_terms()) {
    std::printf("%s", check.table().c_str());
    checked = checked && !check_failed(check);
  }
  const TaylorTestResult taylor = study.taylor_test();
  std::printf("%s", taylor.table().c_str());
  if (!checked || !taylor.passed()) return 1;

  const InverseRun run = study.run("out/custom_energy", &std::cout);
  return std::abs(run.design_values[0] / 1e5 - 1) < 1e-6 ? 0 : 1;
}
