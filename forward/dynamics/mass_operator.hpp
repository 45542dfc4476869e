#pragma once
// The mass matrix of linear simplicial elements as a function of per-element density,
//   M(rho) = sum_e rho_e M_e,
// M_e the unit-density element mass, consistent or lumped, with the formulas of mass_matrix()
// (forward/fem/mass.hpp): [M] = [rho] * [volume], interleaved DOFs. Density is read from the
// parameter vector, p[density_offset + e] for element e, so inertia, gravity and Rayleigh
// damping can differentiate with respect to it.
#include "forward/core/types.hpp"
#include "forward/fem/mass.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

class MassOperator {
 public:
  MassOperator(const Mesh& mesh, MassLumping lumping, int density_offset);
  // A fixed diagonal (lumped) mass, one entry per DOF [mass, or mass length^2 for rotational
  // DOFs], independent of the parameters: the rods' vertex masses and twist inertias
  // (forward/rods/rod_supports.hpp, rod_mass_diagonal). Its density gradients are zero.
  explicit MassOperator(Vector diagonal);
  bool is_fixed_diagonal() const { return fixed_diagonal_.size() > 0; }

  int dim() const { return dim_; }
  int num_dofs() const { return num_dofs_; }
  int num_elements() const { return static_cast<int>(volumes_.size()); }
  int density_offset() const { return density_offset_; }
  MassLumping lumping() const { return lumping_; }

  // out += scale * M(rho) w.
  void add_times(const Vector& p, const Vector& w, Vector& out, double scale = 1.0) const;
  // gradient_p[density_offset + e] += scale * a^T M_e b.
  void add_density_gradient(const Vector& a, const Vector& b, Vector& gradient_p, double scale = 1.0) const;
  // triplets (dof, density_offset + e) of d(M(rho) w)/drho_e = M_e w, times scale.
  void add_density_jacobian(const Vector& w, Triplets& triplets, double scale = 1.0) const;
  // Hessian slots of M (element by element; duplicates summed) and their values scale * M(rho).
  void hessian_pattern(HessianPattern& pattern) const;
  std::size_t pattern_size() const;
  void hessian_values(const Vector& p, double scale, double* values) const;
  // The assembled matrix (for tests, energies and modal analysis).
  SparseMatrix matrix(const Vector& p) const;

 private:
  // Unit-density coefficient of the (a, b) node pair of an element, per component.
  double coefficient(int a, int b) const;
  int dim_, nodes_, num_dofs_, density_offset_;
  MassLumping lumping_;
  Eigen::MatrixXi elements_;
  Eigen::VectorXd volumes_;
  Vector fixed_diagonal_;  // non-empty: a fixed diagonal mass (no elements)
  // Per vertex v: incidences_[vertex_begin_[v] .. vertex_begin_[v + 1]) = e * nodes + a for
  // the elements e with node a at v, by e (add_times runs over vertices).
  std::vector<int> vertex_begin_, incidences_;
};

}  // namespace tailor
