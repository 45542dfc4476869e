#pragma once
// Dead loads: external forces that do not depend on the deformation. They enter the total
// potential as E_ext(x) = -f . x, f a nodal force vector (interleaved like x).
#include "forward/core/energy_term.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

class ExternalForceTerm final : public EnergyTerm {
 public:
  explicit ExternalForceTerm(Vector nodal_forces, std::string label = "external_force")
      : forces_(std::move(nodal_forces)), label_(std::move(label)) {}
  std::string name() const override { return label_; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  bool hessian_is_constant() const override { return true; }  // linear in x
  const Vector& forces() const { return forces_; }

 private:
  Vector forces_;
  std::string label_;
};

// Consistent nodal forces of gravity: each element gives density_e * V_e * g / (dim + 1) to
// each of its vertices (exact for linear shape functions). density: per element [mass /
// volume]; gravity: acceleration vector of size dim.
Vector gravity_forces(const Mesh& mesh, const Eigen::VectorXd& density, const Eigen::VectorXd& gravity);

// Consistent nodal forces of a uniform traction t [force / area] on the given boundary
// facets (rows of vertex indices, as from boundary_facets): each facet gives A_f t / dim to
// each of its vertices.
Vector traction_forces(const Mesh& mesh, const Eigen::MatrixXi& facets, const Eigen::VectorXd& traction);

// Facet measure: area of a triangle in 3D, length of an edge in 2D.
double facet_measure(const Mesh& mesh, const Eigen::Ref<const Eigen::VectorXi>& facet);

}  // namespace tailor
