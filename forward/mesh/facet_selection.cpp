#include <functional>

#include "forward/mesh/mesh.hpp"

namespace tailor {

Eigen::MatrixXi boundary_facets_where(const Mesh& mesh, const std::function<bool(const Eigen::VectorXd&)>& on) {
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  std::vector<int> kept;
  for (int k = 0; k < facets.rows(); ++k) {
    bool all = true;
    for (int a = 0; a < facets.cols() && all; ++a) all = on(mesh.rest_positions.row(facets(k, a)).transpose());
    if (all) kept.push_back(k);
  }
  Eigen::MatrixXi out(static_cast<Eigen::Index>(kept.size()), facets.cols());
  for (std::size_t k = 0; k < kept.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = facets.row(kept[k]);
  return out;
}

}  // namespace tailor
