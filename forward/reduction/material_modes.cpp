#include "forward/reduction/material_modes.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tailor {

MaterialModes material_modes(const Mesh& mesh, int count, const MaterialModeOptions& options) {
  const SparseMatrix L = element_adjacency_laplacian(mesh, options.weighting);  // validates the mesh
  const int m = mesh.num_elements();
  if (count < 1 || count > m - 1)
    throw std::invalid_argument("material_modes: count = " + std::to_string(count) +
                                " is not in [1, num_elements - 1] = [1, " + std::to_string(m - 1) + "]");
  const Eigen::VectorXd volumes = element_volumes(mesh);
  for (int e = 0; e < m; ++e)
    if (!(volumes[e] > 0) || !std::isfinite(volumes[e]))
      throw std::invalid_argument("material_modes: element " + std::to_string(e) +
                                  " has non-positive volume");

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
