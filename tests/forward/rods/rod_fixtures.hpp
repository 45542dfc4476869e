#pragma once
// Small rods for the tests of forward/rods: a rod with its three energy terms in a Model whose
// state holds the positions first and the twists after them.
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "forward/core/model.hpp"
#include "forward/rods/bending_term.hpp"
#include "forward/rods/stretching_term.hpp"
#include "forward/rods/twisting_term.hpp"

namespace tailor::testing {

struct RodSetup {
  std::shared_ptr<DiscreteRod> rod;
  std::unique_ptr<Model> model;
  RodParameterBlocks blocks;
  RodMaterial material;
  Vector p;
  Vector rest;  // rest state (positions, zero twists)
  RodStretchingTerm* stretching = nullptr;
  RodBendingTerm* bending = nullptr;
  RodTwistingTerm* twisting = nullptr;
};

// A rod through `positions` (rows), state layout [positions | twists], uniform material,
// stress-free rest shape; the Model holds the three terms.
inline RodSetup make_rod(const Eigen::MatrixX3d& positions, const RodMaterial& material = {},
                         const Eigen::Vector3d& first_director = Eigen::Vector3d::Zero(),
                         RodTopology topology = RodTopology::open) {
  RodSetup s;
  const int nv = static_cast<int>(positions.rows());
  s.rod = std::make_shared<DiscreteRod>(positions, 0, 3 * nv, first_director, topology);
  s.model = std::make_unique<Model>(s.rod->dof_end());
  s.material = material;
  s.blocks = add_rod_parameters(s.model->parameter_layout(), *s.rod);
  s.p = Vector::Zero(s.model->parameter_layout().size());
  write_rod_parameters(*s.rod, s.blocks, material, s.p);
  s.stretching = &s.model->add(std::make_unique<RodStretchingTerm>(s.rod, material.section, s.blocks));
  s.bending = &s.model->add(std::make_unique<RodBendingTerm>(s.rod, material.section, s.blocks));
  s.twisting = &s.model->add(std::make_unique<RodTwistingTerm>(s.rod, material.section, s.blocks));
  s.rest = Vector::Zero(s.rod->dof_end());
  s.rod->write_rest_state(s.rest);
  return s;
}

// n vertices on a helix of radius a and pitch c per radian, from angle 0 to `turns` turns.
inline Eigen::MatrixX3d helix(int n, double a, double c, double turns) {
  Eigen::MatrixX3d x(n, 3);
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * M_PI * turns * i / (n - 1);
    x.row(i) << a * std::cos(phi), a * std::sin(phi), c * phi;
  }
  return x;
}

// n vertices on the segment from the origin along (1, 0, 0) of length L.
inline Eigen::MatrixX3d straight(int n, double L) {
  Eigen::MatrixX3d x = Eigen::MatrixX3d::Zero(n, 3);
  for (int i = 0; i < n; ++i) x(i, 0) = L * i / (n - 1);
  return x;
}

inline Vector uniform_noise(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector v(n);
  for (auto& e : v) e = u(rng);
  return v;
}

// A term whose gradient is 0.01% too stiff (value and Hessian as the inner term's): a
// derivative check of it must fail.
struct GradientTooStiff final : EnergyTerm {
  const EnergyTerm& inner;
  explicit GradientTooStiff(const EnergyTerm& t) : inner(t) {}
  std::string name() const override { return "gradient 0.01% too stiff"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& r) const override {
    inner.evaluate(x, p, r);
    if (r.gradient) {
      Vector g = Vector::Zero(x.size());
      inner.add_gradient(x, p, g);
      *r.gradient += 1e-4 * g;
    }
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner.hessian_pattern(pattern); }
};

}  // namespace tailor::testing
