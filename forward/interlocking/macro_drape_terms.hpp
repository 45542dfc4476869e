#pragma once
// The other terms of a draped macro-scale sheet (docs/interlocking.md, "Macro-scale model"): a
// quadratic bending energy and a sphere obstacle. DOFs as MacroSheetTerm's: 3 per vertex, deformed
// positions [length].
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor::interlocking {

// Bending of a sheet that is flat at rest, in the quadratic model of Bergou, Wardetzky, Harmon,
// Zorin, Grinspun ("A quadratic bending model for inextensible surfaces", SGP 2006, eq. 7):
//   E = (D / 2) sum_i |(L x)_i|^2 / A_i  over interior vertices i,
// L the rest cotangent Laplacian ((L x)_i = sum_j (cot a_ij + cot b_ij)/2 (x_i - x_j)), A_i the
// barycentric vertex area. (L x)_i = -A_i (Delta x)_i and |Delta x| = 2 |H|, so a cylinder of
// radius R gets D / (2 R^2) per area: D [energy] is the plate's bending stiffness. Exact for
// isometric bending of the flat sheet, and quadratic, so its Hessian is constant; the membrane
// term keeps the sheet near isometric (interlocked elements slide but do not stretch far).
class QuadraticBendingTerm final : public EnergyTerm {
 public:
  QuadraticBendingTerm(const Mesh& flat, double bending_stiffness);
  std::string name() const override { return "sheet_bending"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  bool hessian_is_constant() const override { return true; }

 private:
  struct Row {
    std::vector<int> vertices;    // i and its neighbours
    std::vector<double> weights;  // (L x)_i = sum weights[a] x_(vertices[a])
    double area = 0.0;            // A_i
  };
  std::vector<Row> rows_;
  double stiffness_ = 0.0;
};

// A rigid sphere that the sheet's vertices may not enter: per vertex, with d = |x - c| - R,
//   E = kappa b(d),   b(d) = -(d - d_hat)^2 log(d / d_hat) for d < d_hat, else 0
// (IPC's barrier, Li et al. 2020, eq. 6), +infinity for d <= 0. Vertex contact only: between the
// vertices a triangle's face can dip under the surface by its sagitta (about h^2 / (8 R) for edge
// length h), which the report states. max_step is the exact first time along the step at which a
// vertex comes to a fifth of its current gap (a quadratic in t), like CCD.
class SphereObstacleTerm final : public EnergyTerm {
 public:
  SphereObstacleTerm(int num_vertices, const Eigen::Vector3d& center, double radius, double activation,
                     double stiffness);
  std::string name() const override { return "sphere_obstacle"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  double max_step(const Vector& x, const Vector& dx) const override;
  // Per vertex d = |x - c| - R [length].
  Eigen::VectorXd gaps(const Vector& x) const;

 private:
  int num_vertices_;
  Eigen::Vector3d center_;
  double radius_, activation_, stiffness_;
};

}  // namespace tailor::interlocking
