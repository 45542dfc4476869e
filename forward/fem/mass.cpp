#include "forward/fem/mass.hpp"

#include <stdexcept>

namespace tailor {

SparseMatrix mass_matrix(const Mesh& mesh, const Eigen::VectorXd& density, MassLumping lumping) {
  const int dim = mesh.dim();
  const int nodes = dim + 1;
  if (density.size() != mesh.num_elements()) throw std::invalid_argument("mass_matrix: one density per element expected");
  const Eigen::VectorXd volumes = element_volumes(mesh);
  Triplets triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.num_elements()) * nodes * nodes * dim);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const double m = density[e] * volumes[e];
    for (int a = 0; a < nodes; ++a) {
      const int va = mesh.elements(e, a);
      if (lumping == MassLumping::lumped) {
        for (int i = 0; i < dim; ++i) triplets.emplace_back(dim * va + i, dim * va + i, m / nodes);
        continue;
      }
      for (int b = 0; b < nodes; ++b) {
        const int vb = mesh.elements(e, b);
        const double mab = m * (a == b ? 2.0 : 1.0) / (nodes * (nodes + 1));
        for (int i = 0; i < dim; ++i) triplets.emplace_back(dim * va + i, dim * vb + i, mab);
      }
    }
  }
  const int n = dim * mesh.num_vertices();
  SparseMatrix M(n, n);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

}  // namespace tailor
