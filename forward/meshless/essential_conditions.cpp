#include "forward/meshless/essential_conditions.hpp"

#include <Eigen/LU>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace tailor {

MlsEssentialConditions mls_transformation(const MlsShapeFunctions& mls, const std::vector<int>& nodes,
                                          const Eigen::MatrixXd& targets) {
  const int n = mls.num_nodes(), nb = static_cast<int>(nodes.size());
  if (targets.rows() != nb || targets.cols() != 3)
    throw std::invalid_argument("mls_transformation: targets must be " + std::to_string(nb) + " x 3");
  std::vector<int> constrained_index(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < nb; ++i) {
    const int b = nodes[static_cast<std::size_t>(i)];
    if (b < 0 || b >= n) throw std::invalid_argument("mls_transformation: node " + std::to_string(b) + " out of range");
    if (constrained_index[static_cast<std::size_t>(b)] >= 0)
      throw std::invalid_argument("mls_transformation: node " + std::to_string(b) + " listed twice");
    constrained_index[static_cast<std::size_t>(b)] = i;
  }
  // Free nodes in increasing order; column of (free node, component) = 3 * rank + component.
  std::vector<int> free_rank(static_cast<std::size_t>(n), -1);
  int num_free_nodes = 0;
  for (int a = 0; a < n; ++a)
    if (constrained_index[static_cast<std::size_t>(a)] < 0) free_rank[static_cast<std::size_t>(a)] = num_free_nodes++;

  Eigen::MatrixXd C_BB = Eigen::MatrixXd::Zero(nb, nb);
  std::vector<int> near;  // free nodes reaching some collocation point
  std::vector<int> near_index(static_cast<std::size_t>(n), -1);
  std::vector<std::vector<std::pair<int, double>>> C_BO(static_cast<std::size_t>(nb));
  for (int i = 0; i < nb; ++i) {
    const MlsValues v = mls.evaluate(mls.nodes().row(nodes[static_cast<std::size_t>(i)]).transpose());
    for (std::size_t t = 0; t < v.nodes.size(); ++t) {
      const int a = v.nodes[t];
      const double phi = v.values[static_cast<Eigen::Index>(t)];
      if (constrained_index[static_cast<std::size_t>(a)] >= 0) {
        C_BB(i, constrained_index[static_cast<std::size_t>(a)]) = phi;
      } else {
        if (near_index[static_cast<std::size_t>(a)] < 0) {
          near_index[static_cast<std::size_t>(a)] = static_cast<int>(near.size());
          near.push_back(a);
        }
        C_BO[static_cast<std::size_t>(i)].emplace_back(near_index[static_cast<std::size_t>(a)], phi);
      }
    }
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(C_BB);
  const double rcond = nb > 0 ? lu.rcond() : 1.0;
  if (!(rcond >= 1e-12)) {
    std::ostringstream s;
    s << "mls_transformation: the collocation matrix of the " << nb
      << " constrained nodes is singular or ill-conditioned (reciprocal condition " << rcond << ")";
    throw std::invalid_argument(s.str());
  }
  Eigen::MatrixXd C_near = Eigen::MatrixXd::Zero(nb, static_cast<Eigen::Index>(near.size()));
  for (int i = 0; i < nb; ++i)
    for (const auto& [j, phi] : C_BO[static_cast<std::size_t>(i)]) C_near(i, j) += phi;
  const Eigen::MatrixXd K = nb > 0 ? Eigen::MatrixXd(lu.solve(C_near)) : Eigen::MatrixXd(0, 0);
  const Eigen::MatrixXd x_particular = nb > 0 ? Eigen::MatrixXd(lu.solve(targets)) : Eigen::MatrixXd(0, 3);

  Vector x0 = Vector::Zero(3 * n);
  Triplets triplets;
  for (int a = 0; a < n; ++a) {
    const int r = free_rank[static_cast<std::size_t>(a)];
    if (r >= 0) {
      for (int k = 0; k < 3; ++k) triplets.emplace_back(3 * a + k, 3 * r + k, 1.0);
      continue;
    }
    const int i = constrained_index[static_cast<std::size_t>(a)];
    for (int k = 0; k < 3; ++k) {
      x0[3 * a + k] = x_particular(i, k);
      for (std::size_t j = 0; j < near.size(); ++j)
        if (K(i, static_cast<Eigen::Index>(j)) != 0.0)
          triplets.emplace_back(3 * a + k, 3 * free_rank[static_cast<std::size_t>(near[j])] + k,
                                -K(i, static_cast<Eigen::Index>(j)));
    }
  }
  SparseMatrix S(3 * n, 3 * num_free_nodes);
  S.setFromTriplets(triplets.begin(), triplets.end());
  return MlsEssentialConditions{Elimination(std::move(x0), std::move(S)), 1.0 / rcond};
}

}  // namespace tailor
