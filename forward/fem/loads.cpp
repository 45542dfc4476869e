#include "forward/fem/loads.hpp"

#include <Eigen/Geometry>
#include <stdexcept>

namespace tailor {

void ExternalForceTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (x.size() != forces_.size())
    throw std::invalid_argument("ExternalForceTerm '" + label_ + "': force vector size does not match the state");
  if (request.value) *request.value -= forces_.dot(x);
  if (request.gradient) *request.gradient -= forces_;
}

Vector gravity_forces(const Mesh& mesh, const Eigen::VectorXd& density, const Eigen::VectorXd& gravity) {
  const int dim = mesh.dim();
  if (gravity.size() != dim) throw std::invalid_argument("gravity_forces: gravity must have one component per dimension");
  if (density.size() != mesh.num_elements()) throw std::invalid_argument("gravity_forces: one density per element expected");
  const Eigen::VectorXd volumes = element_volumes(mesh);
  Vector f = Vector::Zero(dim * mesh.num_vertices());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const double share = density[e] * volumes[e] / (dim + 1);
    for (int a = 0; a <= dim; ++a) f.segment(dim * mesh.elements(e, a), dim) += share * gravity;
  }
  return f;
}

double facet_measure(const Mesh& mesh, const Eigen::Ref<const Eigen::VectorXi>& facet) {
  if (mesh.dim() == 3) {
    const Eigen::Vector3d a = mesh.rest_positions.row(facet[0]), b = mesh.rest_positions.row(facet[1]),
                          c = mesh.rest_positions.row(facet[2]);
    return 0.5 * (b - a).cross(c - a).norm();
  }
  return (mesh.rest_positions.row(facet[1]) - mesh.rest_positions.row(facet[0])).norm();
}

Vector traction_forces(const Mesh& mesh, const Eigen::MatrixXi& facets, const Eigen::VectorXd& traction) {
  const int dim = mesh.dim();
  if (traction.size() != dim) throw std::invalid_argument("traction_forces: traction must have one component per dimension");
  if (facets.rows() > 0 && facets.cols() != dim) throw std::invalid_argument("traction_forces: facets must have dim vertices");
  Vector f = Vector::Zero(dim * mesh.num_vertices());
  for (int k = 0; k < facets.rows(); ++k) {
    const Eigen::VectorXi facet = facets.row(k).transpose();
    const double share = facet_measure(mesh, facet) / dim;
    for (int a = 0; a < dim; ++a) f.segment(dim * facet[a], dim) += share * traction;
  }
  return f;
}

}  // namespace tailor
