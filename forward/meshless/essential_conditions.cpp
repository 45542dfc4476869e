#include "forward/meshless/essential_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace tailor {

namespace {

// Dense LU with partial pivoting, P A = L U (Golub & Van Loan, Matrix Computations, algorithm
// 3.4.1), with Hager's estimate of the 1-norm of A^-1 for the reciprocal condition number
// (Hager 1984; Higham, Accuracy and Stability of Numerical Algorithms, algorithm 15.1). Written
// out because Eigen's blocked PartialPivLU doubled this file's compile time, for collocation
// matrices of a few hundred rows at most.
class CollocationLu {
 public:
  explicit CollocationLu(Eigen::MatrixXd A) : n_(A.rows()), lu_(std::move(A)), row_(static_cast<std::size_t>(n_)) {
    for (Eigen::Index j = 0; j < n_; ++j) norm1_ = std::max(norm1_, lu_.col(j).cwiseAbs().sum());
    for (Eigen::Index i = 0; i < n_; ++i) row_[static_cast<std::size_t>(i)] = i;
    for (Eigen::Index k = 0; k < n_; ++k) {
      Eigen::Index pivot = k;
      for (Eigen::Index i = k + 1; i < n_; ++i)
        if (std::abs(lu_(i, k)) > std::abs(lu_(pivot, k))) pivot = i;
      if (lu_(pivot, k) == 0.0) {
        singular_ = true;
        return;
      }
      if (pivot != k) {
        lu_.row(k).swap(lu_.row(pivot));
        std::swap(row_[static_cast<std::size_t>(k)], row_[static_cast<std::size_t>(pivot)]);
      }
      const double inverse = 1.0 / lu_(k, k);
      for (Eigen::Index i = k + 1; i < n_; ++i) lu_(i, k) *= inverse;
      for (Eigen::Index j = k + 1; j < n_; ++j) {
        const double u = lu_(k, j);
        if (u != 0.0)
          for (Eigen::Index i = k + 1; i < n_; ++i) lu_(i, j) -= lu_(i, k) * u;
      }
    }
  }

  // A x = b, in place.
  void solve(double* b) const {
    std::vector<double> c(static_cast<std::size_t>(n_));
    for (Eigen::Index i = 0; i < n_; ++i) c[static_cast<std::size_t>(i)] = b[row_[static_cast<std::size_t>(i)]];
    for (Eigen::Index i = 0; i < n_; ++i)
      for (Eigen::Index j = 0; j < i; ++j) c[static_cast<std::size_t>(i)] -= lu_(i, j) * c[static_cast<std::size_t>(j)];
    for (Eigen::Index i = n_ - 1; i >= 0; --i) {
      for (Eigen::Index j = i + 1; j < n_; ++j) c[static_cast<std::size_t>(i)] -= lu_(i, j) * c[static_cast<std::size_t>(j)];
      c[static_cast<std::size_t>(i)] /= lu_(i, i);
    }
    std::copy(c.begin(), c.end(), b);
  }

  // A^T x = b, in place (A^T = U^T L^T P).
  void solve_transpose(double* b) const {
    std::vector<double> c(b, b + n_);
    for (Eigen::Index i = 0; i < n_; ++i) {
      for (Eigen::Index j = 0; j < i; ++j) c[static_cast<std::size_t>(i)] -= lu_(j, i) * c[static_cast<std::size_t>(j)];
      c[static_cast<std::size_t>(i)] /= lu_(i, i);
    }
    for (Eigen::Index i = n_ - 1; i >= 0; --i)
      for (Eigen::Index j = i + 1; j < n_; ++j) c[static_cast<std::size_t>(i)] -= lu_(j, i) * c[static_cast<std::size_t>(j)];
    for (Eigen::Index i = 0; i < n_; ++i) b[row_[static_cast<std::size_t>(i)]] = c[static_cast<std::size_t>(i)];
  }

  // 1 / (|A|_1 est|A^-1|_1); 0 when a pivot vanished.
  double rcond() const {
    if (singular_ || norm1_ == 0.0) return 0.0;
    Eigen::VectorXd x = Eigen::VectorXd::Constant(n_, 1.0 / static_cast<double>(n_)), y(n_), z(n_);
    double estimate = 0.0;
    for (int iteration = 0; iteration < 5; ++iteration) {
      y = x;
      solve(y.data());
      const double norm = y.cwiseAbs().sum();
      if (iteration > 0 && norm <= estimate) break;
      estimate = norm;
      for (Eigen::Index i = 0; i < n_; ++i) z[i] = y[i] >= 0.0 ? 1.0 : -1.0;
      solve_transpose(z.data());
      Eigen::Index j = 0;
      if (z.cwiseAbs().maxCoeff(&j) <= z.dot(x)) break;
      x.setZero();
      x[j] = 1.0;
    }
    return std::isfinite(estimate) ? 1.0 / (norm1_ * estimate) : 0.0;
  }

 private:
  Eigen::Index n_;
  Eigen::MatrixXd lu_;
  std::vector<Eigen::Index> row_;  // row i of P A is row row_[i] of A
  double norm1_ = 0.0;
  bool singular_ = false;
};

}  // namespace

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
    const CollocationLu lu(std::move(C_BB));
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
    Eigen::MatrixXd K = std::move(C_near);
    for (Eigen::Index j = 0; j < K.cols(); ++j) lu.solve(K.col(j).data());
    Eigen::VectorXd particular = c.targets;
    lu.solve(particular.data());
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
