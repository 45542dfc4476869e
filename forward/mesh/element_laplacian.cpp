#include "forward/mesh/element_laplacian.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace tailor {
namespace {

void check_mesh(const Mesh& mesh, const char* who) {
  if (mesh.num_elements() == 0) throw std::invalid_argument(std::string(who) + ": mesh has no elements");
  if ((mesh.dim() != 2 && mesh.dim() != 3) || mesh.elements.cols() != mesh.dim() + 1)
    throw std::invalid_argument(std::string(who) +
                                ": mesh must be simplicial in 2D (triangles) or 3D (tetrahedra)");
  if (mesh.elements.minCoeff() < 0 || mesh.elements.maxCoeff() >= mesh.num_vertices())
    throw std::invalid_argument(std::string(who) + ": element vertex index out of range");
}

Eigen::VectorXd centroid(const Mesh& mesh, int e) {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(mesh.dim());
  for (Eigen::Index k = 0; k < mesh.elements.cols(); ++k)
    c += mesh.rest_positions.row(mesh.elements(e, k)).transpose();
  return c / static_cast<double>(mesh.elements.cols());
}

// Measure (area in 3D, length in 2D) of the facet shared by elements e and f: the vertices of
// e that also belong to f.
double shared_facet_measure(const Mesh& mesh, int e, int f) {
  std::vector<int> shared;
  for (Eigen::Index i = 0; i < mesh.elements.cols(); ++i) {
    const int v = mesh.elements(e, i);
    for (Eigen::Index j = 0; j < mesh.elements.cols(); ++j)
      if (mesh.elements(f, j) == v) {
        shared.push_back(v);
        break;
      }
  }
  if (static_cast<int>(shared.size()) != mesh.dim()) return 0.0;
  const auto p = [&](int k) -> Eigen::VectorXd {
    return mesh.rest_positions.row(shared[static_cast<std::size_t>(k)]).transpose();
  };
  if (mesh.dim() == 2) return (p(1) - p(0)).norm();
  const Eigen::Vector3d a = p(1) - p(0), b = p(2) - p(0);
  return 0.5 * a.cross(b).norm();
}

}  // namespace

Vector element_adjacency_weights(const Mesh& mesh, const Eigen::MatrixXi& pairs, AdjacencyWeighting weighting) {
  check_mesh(mesh, "element_adjacency_weights");
  Vector w = Vector::Ones(pairs.rows());
  if (weighting == AdjacencyWeighting::unit) return w;
  for (Eigen::Index k = 0; k < pairs.rows(); ++k) {
    const int e = pairs(k, 0), f = pairs(k, 1);
    const double measure = shared_facet_measure(mesh, e, f);
    const double distance = (centroid(mesh, e) - centroid(mesh, f)).norm();
    w[k] = measure / distance;
    if (!(measure > 0) || !(distance > 0) || !std::isfinite(w[k]))
      throw std::invalid_argument("element_adjacency_weights: degenerate shared facet or coincident centroids between elements " +
                                  std::to_string(e) + " and " + std::to_string(f));
  }
  return w;
}

SparseMatrix element_adjacency_laplacian(const Mesh& mesh, AdjacencyWeighting weighting) {
  check_mesh(mesh, "element_adjacency_laplacian");
  const Eigen::MatrixXi pairs = element_adjacency(mesh);
  const Vector weights = element_adjacency_weights(mesh, pairs, weighting);
  Triplets triplets;
  triplets.reserve(4 * static_cast<std::size_t>(pairs.rows()));
  for (Eigen::Index k = 0; k < pairs.rows(); ++k) {
    const int e = pairs(k, 0), f = pairs(k, 1);
    const double w = weights[k];
    triplets.emplace_back(e, e, w);
    triplets.emplace_back(f, f, w);
    triplets.emplace_back(e, f, -w);
    triplets.emplace_back(f, e, -w);
  }
  SparseMatrix L(mesh.num_elements(), mesh.num_elements());
  L.setFromTriplets(triplets.begin(), triplets.end());
  L.makeCompressed();
  return L;
}

}  // namespace tailor
