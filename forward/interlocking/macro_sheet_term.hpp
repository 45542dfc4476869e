#pragma once
// The macro-scale interlocking sheet (docs/interlocking.md, "Macro-scale model"): a membrane on a
// triangle mesh whose admissible strains are the fitted native boundary (macro_boundary_fit.hpp).
//
// DOFs: 3 per vertex, the deformed positions [length], interleaved (x0, y0, z0, x1, ...). Rest: the
// flat mesh (2D triangles, its x-y plane the material frame). Per element, F = [x1 - x0, x2 - x0]
// Dm^-1 (3 x 2), C = F^T F, and the strain is Biot's, E = U - I with U = sqrt(C) in the material
// frame, the measure of the native sweep (F = I + s G symmetric there, so E = s G). With no
// eigen-decomposition: U = (C + sqrt(det C) I) / sqrt(tr C + 2 sqrt(det C)) (2 x 2 closed form),
//   rho = |E| (Frobenius),  n = (u, v, w) its direction (macro_anisotropic_fit.hpp),  g = 1 - rho / r(n),
// r the admissible set's radius (MacroStrainSet: the isotropic fit r(u), u = (e_1 + e_2) / (sqrt(2)
// rho) of the principal strains, or the anisotropic fit r(u, v, w)).
// Energy per rest area [energy / area]:
//   psi = (k / 2) rho^2 + kappa b(g),   b(g) = -(g - g_hat)^2 log(g / g_hat) for g < g_hat, else 0
// (the clamped log barrier of IPC, Li et al. 2020, eq. 6, in the margin g instead of a distance: C2
// at g_hat, infinite at g = 0). k is a small stiffness that keeps the free motion of the
// interlocked elements well posed (nearly stress-free; (k/2) rho^2 is the as-rigid-as-possible
// membrane energy); kappa b locks the sheet at the boundary. Outside the set (g <= 0, or a
// degenerate element, I2 <= 0) the energy is +infinity, and max_step keeps Newton inside.
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/interlocking/macro_anisotropic_fit.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor::interlocking {

struct MacroSheetMaterial {
  double stiffness = 1.0;           // k [energy / area]
  double barrier_stiffness = 1.0;   // kappa [energy / area]
  double barrier_activation = 0.1;  // g_hat: the barrier acts where g < g_hat (rho > (1 - g_hat) r)
};

// Triangles of the sheet in the element loop's shape (element_loop.hpp).
struct SheetTriangles {
  static constexpr int kNodes = 3;
  std::vector<Eigen::Matrix<int, 3, 1>> vertices;
  std::vector<Eigen::Matrix<double, 3, 2>> gradients;  // row a: d F / d x_a (F = sum_a x_a row_a)
  std::vector<double> areas;                           // rest areas [length^2]
  int size() const { return static_cast<int>(vertices.size()); }
};

class MacroSheetTerm final : public EnergyTerm {
 public:
  // `flat`: a 2D triangle mesh (the rest sheet, counter-clockwise triangles). Throws
  // std::invalid_argument for another mesh, degenerate triangles or bad material constants.
  MacroSheetTerm(const Mesh& flat, MacroStrainSet set, MacroSheetMaterial material);

  std::string name() const override { return "interlocking_sheet"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  // The largest fraction of dx before an element's margin falls to a fifth of its current value
  // (the margin sampled at 16 points of the step, then bisected where it crossed): like CCD for
  // contact, the step never leaves the admissible set (the 1/5 leaves the line search room).
  double max_step(const Vector& x, const Vector& dx) const override;

  // Per element at full state x: principal strains (e_1 >= e_2) and the margin g (row k: element k).
  Eigen::MatrixXd principal_strains(const Vector& x) const;
  Eigen::VectorXd margins(const Vector& x) const;
  // Per element: the Biot strain (e_xx, e_yy, e_xy) in the material frame.
  Eigen::MatrixXd strains(const Vector& x) const;

  const MacroStrainSet& set() const { return set_; }
  const MacroSheetMaterial& material() const { return material_; }
  const SheetTriangles& triangles() const { return triangles_; }

 private:
  double margin(const Vector& x, int k) const;
  SheetTriangles triangles_;
  MacroStrainSet set_;
  MacroSheetMaterial material_;
};

}  // namespace tailor::interlocking
