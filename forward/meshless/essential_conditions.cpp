#include "forward/meshless/essential_conditions.hpp"

#include <Eigen/LU>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace tailor {

MlsEssentialConditions mls_transformation(const MlsShapeFunctions& mls,
                                          const std::array<MlsComponentConditions, 3>& components) {
  const int n = mls.num_nodes();
  // constrained[3a + k]: index of (a, k) in its component's list, or -1.
  std::vector<int> constrained(static_cast<std::size_t>(3 * n), -1);
  for (int k = 0; k < 3; ++k) {
    const MlsComponentConditions& c = components[static_cast<std::size_t>(k)];
    if (c.targets.size() != static_cast<Eigen::Index>(c.nodes.size()))
      throw std::invalid_argument("mls_transformation: component " + std::to_string(k) + " has " +
                                  std::to_string(c.nodes.size()) + " nodes and " + std::to_string(c.targets.size()) +
                                  " targets");
    for (std::size_t i = 0; i < c.nodes.size(); ++i) {
      const int b = c.nodes[i];
      if (b < 0 || b >= n) throw std::invalid_argument("mls_transformation: node " + std::to_string(b) + " out of range");
      int& slot = constrained[static_cast<std::size_t>(3 * b + k)];
      if (slot >= 0)
        throw std::invalid_argument("mls_transformation: node " + std::to_string(b) + " listed twice for component " +
                                    std::to_string(k));
      slot = static_cast<int>(i);
    }
  }
  // Free unknowns: the unconstrained DOFs in increasing order.
  std::vector<int> column(static_cast<std::size_t>(3 * n), -1);
  int num_free = 0;
  for (int d = 0; d < 3 * n; ++d)
    if (constrained[static_cast<std::size_t>(d)] < 0) column[static_cast<std::size_t>(d)] = num_free++;

  Vector x0 = Vector::Zero(3 * n);
  Triplets triplets;
  for (int d = 0; d < 3 * n; ++d)
    if (column[static_cast<std::size_t>(d)] >= 0) triplets.emplace_back(d, column[static_cast<std::size_t>(d)], 1.0);
  double worst_rcond = 1.0;
  for (int k = 0; k < 3; ++k) {
    const MlsComponentConditions& c = components[static_cast<std::size_t>(k)];
    const int nb = static_cast<int>(c.nodes.size());
    if (nb == 0) continue;
    // C_BB and C_BO of this component; O restricted to the free nodes reaching a collocation point.
    Eigen::MatrixXd C_BB = Eigen::MatrixXd::Zero(nb, nb);
    std::vector<int> near, near_index(static_cast<std::size_t>(n), -1);
    std::vector<std::vector<std::pair<int, double>>> C_BO(static_cast<std::size_t>(nb));
    for (int i = 0; i < nb; ++i) {
      const MlsValues v = mls.evaluate(mls.nodes().row(c.nodes[static_cast<std::size_t>(i)]).transpose());
      for (std::size_t t = 0; t < v.nodes.size(); ++t) {
        const int a = v.nodes[t];
        const double phi = v.values[static_cast<Eigen::Index>(t)];
        const int j = constrained[static_cast<std::size_t>(3 * a + k)];
        if (j >= 0) {
          C_BB(i, j) = phi;
          continue;
        }
        if (near_index[static_cast<std::size_t>(a)] < 0) {
          near_index[static_cast<std::size_t>(a)] = static_cast<int>(near.size());
          near.push_back(a);
        }
        C_BO[static_cast<std::size_t>(i)].emplace_back(near_index[static_cast<std::size_t>(a)], phi);
      }
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(C_BB);
    const double rcond = lu.rcond();
    if (!(rcond >= 1e-12)) {
      std::ostringstream s;
      s << "mls_transformation: the collocation matrix of the " << nb << " nodes constrained in component " << k
        << " is singular or ill-conditioned (reciprocal condition " << rcond << ")";
      throw std::invalid_argument(s.str());
    }
    worst_rcond = std::min(worst_rcond, rcond);
    Eigen::MatrixXd C_near = Eigen::MatrixXd::Zero(nb, static_cast<Eigen::Index>(near.size()));
    for (int i = 0; i < nb; ++i)
      for (const auto& [j, phi] : C_BO[static_cast<std::size_t>(i)]) C_near(i, j) += phi;
    // x_B = C_BB^-1 t - (C_BB^-1 C_BO) x_O.
    const Eigen::MatrixXd K = lu.solve(C_near);
    const Eigen::VectorXd particular = lu.solve(c.targets);
    for (int i = 0; i < nb; ++i) {
      const int d = 3 * c.nodes[static_cast<std::size_t>(i)] + k;
      x0[d] = particular[i];
      for (std::size_t j = 0; j < near.size(); ++j)
        if (K(i, static_cast<Eigen::Index>(j)) != 0.0)
          triplets.emplace_back(d, column[static_cast<std::size_t>(3 * near[j] + k)], -K(i, static_cast<Eigen::Index>(j)));
    }
  }
  SparseMatrix S(3 * n, num_free);
  S.setFromTriplets(triplets.begin(), triplets.end());
  return MlsEssentialConditions{Elimination(std::move(x0), std::move(S)), 1.0 / worst_rcond};
}

MlsEssentialConditions mls_transformation(const MlsShapeFunctions& mls, const std::vector<int>& nodes,
                                          const Eigen::MatrixXd& targets) {
  if (targets.rows() != static_cast<Eigen::Index>(nodes.size()) || targets.cols() != 3)
    throw std::invalid_argument("mls_transformation: targets must be " + std::to_string(nodes.size()) + " x 3");
  std::array<MlsComponentConditions, 3> components;
  for (int k = 0; k < 3; ++k) components[static_cast<std::size_t>(k)] = {nodes, targets.col(k)};
  return mls_transformation(mls, components);
}

}  // namespace tailor
