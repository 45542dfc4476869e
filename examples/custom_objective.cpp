// An objective of the user's own on a scene file: the mean displacement of some vertices along a
// direction should reach a target. The term type is registered from here, so that the scene
// (tip_deflection.json) names it in its objective list like one of tailor's own.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <vector>

#include "problems/fem/study.hpp"

using namespace tailor;

// J(x) = 1/2 ((m - t) / t)^2, m = d . (mean over the vertices of x_v - X_v), t the target.
class MeanDisplacement final : public Objective {
 public:
  MeanDisplacement(std::vector<int> vertices, Vector rest, Eigen::Vector3d direction, double target)
      : vertices_(std::move(vertices)), rest_(std::move(rest)), d_(direction.normalized()), t_(target) {}
  std::string name() const override { return "mean_displacement"; }
  double mean(const Vector& x) const { return along(x - rest_); }
  double value(const Vector& x, const Vector&) const override {
    const double r = (mean(x) - t_) / t_;
    return 0.5 * r * r;
  }
  // dJ/dx_v = (m - t) / t^2 * d / n on each vertex; J_xx dx = a (a . dx) / t^2, a = d / n per vertex.
  void add_gradient_x(const Vector& x, const Vector&, Vector& gx) const override {
    add_along(gx, (mean(x) - t_) / (t_ * t_));
  }
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector&, const Vector&, const Vector& dx, const Vector&, Vector& out_x,
                         Vector&) const override {
    add_along(out_x, along(dx) / (t_ * t_));
  }

 private:
  double along(const Vector& u) const {  // d . (mean of u over the vertices)
    double m = 0.0;
    for (int v : vertices_) m += d_.dot(u.segment<3>(3 * v));
    return m / static_cast<double>(vertices_.size());
  }
  void add_along(Vector& out, double factor) const {
    for (int v : vertices_) out.segment<3>(3 * v) += factor / static_cast<double>(vertices_.size()) * d_;
  }
  std::vector<int> vertices_;
  Vector rest_;
  Eigen::Vector3d d_;
  double t_;
};

int main(int argc, char** argv) {
  register_objective_term({"mean_displacement",
                           true,
                           {"vertices", "direction", "target"},
                           {"vertices", "direction", "target"},
                           [](const ObjectiveTermContext& c) {
                             return std::make_shared<MeanDisplacement>(
                                 c.vertices("vertices"), c.problem.setup.rest_state(),
                                 c.node.at("direction").vector(3), c.node.at("target").positive());
                           }});
  Study study = Study::from_file(argc > 1 ? argv[1] : EXAMPLE_SCENE);  // EXAMPLE_SCENE: CMakeLists.txt

  const TaylorTestResult taylor = study.taylor_test();  // checks MeanDisplacement's gradient too
  std::printf("%s", taylor.table().c_str());
  if (!taylor.passed()) return 1;

  const InverseRun run = study.run("out/custom_objective", &std::cout);
  const auto& term = dynamic_cast<const MeanDisplacement&>(*run.problem->terms.front().term);
  const double reached = term.mean(run.solution.positions);
  std::printf("mean tip displacement %.9g (target 0.2) with E = %.6g\n", reached, run.design_values[0]);
  return std::abs(reached / 0.2 - 1) < 1e-6 ? 0 : 1;
}
