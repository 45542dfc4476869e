#include "forward/reduction/material_modes.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
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

SparseMatrix element_adjacency_laplacian(const Mesh& mesh, ModeWeighting weighting) {
  check_mesh(mesh, "element_adjacency_laplacian");
  const Eigen::MatrixXi pairs = element_adjacency(mesh);
  Triplets triplets;
  triplets.reserve(4 * static_cast<std::size_t>(pairs.rows()));
  for (Eigen::Index k = 0; k < pairs.rows(); ++k) {
    const int e = pairs(k, 0), f = pairs(k, 1);
    double w = 1.0;
    if (weighting == ModeWeighting::facet_over_distance) {
      const double measure = shared_facet_measure(mesh, e, f);
      const double distance = (centroid(mesh, e) - centroid(mesh, f)).norm();
      w = measure / distance;
      if (!(measure > 0) || !(distance > 0) || !std::isfinite(w))
        throw std::invalid_argument(
            "element_adjacency_laplacian: degenerate shared facet or coincident centroids between elements " +
            std::to_string(e) + " and " + std::to_string(f));
    }
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

MaterialModes material_modes(const Mesh& mesh, int count, const MaterialModeOptions& options) {
  check_mesh(mesh, "material_modes");
  const int m = mesh.num_elements();
  if (count < 1 || count > m - 1)
    throw std::invalid_argument("material_modes: count = " + std::to_string(count) +
                                " is not in [1, num_elements - 1] = [1, " + std::to_string(m - 1) + "]");
  const Eigen::VectorXd volumes = element_volumes(mesh);
  for (int e = 0; e < m; ++e)
    if (!(volumes[e] > 0) || !std::isfinite(volumes[e]))
      throw std::invalid_argument("material_modes: element " + std::to_string(e) +
                                  " has non-positive volume");

  const SparseMatrix L = element_adjacency_laplacian(mesh, options.weighting);
  SparseMatrix V(m, m);
  V.reserve(Eigen::VectorXi::Ones(m));
  for (int e = 0; e < m; ++e) V.insert(e, e) = volumes[e];
  V.makeCompressed();

  MaterialModes result;
  result.solve = generalized_eigenpairs(L, V, count, options.eigen);
  if (!result.solve.success)
    throw std::runtime_error("material_modes: eigen solve failed: " + result.solve.message);
  result.modes = std::move(result.solve.eigenvectors);
  result.solve.eigenvectors.resize(0, 0);
  result.eigenvalues = result.solve.eigenvalues;
  return result;
}

}  // namespace tailor
