#pragma once
// The damping-design test piece: a cantilever plate (a leaf-like strip of linear tets clamped
// at x = 0) with inertia, linear elasticity and example-based damping on top of Rayleigh
// damping (Xu & Barbic 2017), with its lowest vibration modes for measuring.
// p = [youngs_modulus (m), poisson_ratio (m), density (m), alpha, beta, curve controls].
#include <memory>
#include <vector>

#include "forward/dynamics/example_damping_setup.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

struct DampingPlateOptions {
  double length = 1.0, width = 0.12, thickness = 0.06;  // [length]
  int cells_length = 20, cells_width = 3, cells_thickness = 2;
  double youngs_modulus = 1e5, poisson_ratio = 0.3, density = 1.0;
  double alpha = 0.4, beta = 5e-4;  // Rayleigh [1/time], [time]
  // Examples as eigenmode indices (0 = lowest), each with its curve and control values.
  std::vector<int> example_modes = {0, 1};
  std::vector<DampingCurve> curves;  // empty: constant scales
  std::vector<Vector> controls;      // empty: all 1 (plain Rayleigh)
  int measured_modes = 3;            // modes computed for measurement
};

struct DampingPlate {
  Mesh mesh;
  std::unique_ptr<Model> model;
  DynamicTerms dynamics;
  ExampleDampingTerms damping;
  Vector rest, p;
  SparseMatrix mass, stiffness;  // at p (full DOFs)
  Matrix modes;                  // measured modes, full DOFs, M-orthonormal
  Vector omega;                  // their angular frequencies [rad / time]
  std::vector<int> tip_vertices;

  ExampleDamping& term() const { return *damping.damping; }
  // Sets example i's control values in p.
  void set_controls(int i, const Vector& values);
  // Rayleigh's decay rate of the amplitude of mode k, (alpha + beta omega_k^2) / 2 [1/time].
  double rayleigh_decay_rate(int k) const;
};

// Throws std::invalid_argument for inconsistent options (curves/controls not one per example).
DampingPlate make_damping_plate(const DampingPlateOptions& options);

}  // namespace tailor
