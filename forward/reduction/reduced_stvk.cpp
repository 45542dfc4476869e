#include "forward/reduction/reduced_stvk.hpp"

#include <Eigen/Cholesky>
#include <chrono>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "forward/fem/elastic_term.hpp"

namespace tailor {
namespace {

// Adds the element columns Y_e of one elastic term to the lower triangle of gram.
template <int Dim>
void accumulate(const ElasticTerm<Dim>& term, const Vector& p, const Matrix& basis_t,
                const std::vector<int>& pair, Matrix& gram) {
  constexpr int kComponents = Dim * (Dim + 1) / 2;  // independent strain components
  constexpr int kNodes = Dim + 1;
  const int r = static_cast<int>(basis_t.rows());
  const int num_pairs = r * (r + 1) / 2, width = r + num_pairs;
  const int num = static_cast<int>(term.elements().size());
  constexpr int kChunk = 128;
  // Component c <-> (a, b): the diagonal first, then the off-diagonal pairs.
  int comp_a[kComponents], comp_b[kComponents];
  for (int c = 0, k = Dim; c < Dim; ++c) {
    comp_a[c] = comp_b[c] = c;
    for (int d = c + 1; d < Dim; ++d, ++k) comp_a[k] = c, comp_b[k] = d;
  }

#pragma omp parallel
  {
    Matrix local = Matrix::Zero(width, width);
    Matrix y(width, kComponents * kChunk);
    Matrix g(Dim * Dim, r);  // row i + Dim * b: d(grad u)_ib / dq
    Matrix outer(r, r);
#pragma omp for schedule(dynamic)
    for (int start = 0; start < num; start += kChunk) {
      const int count = std::min(kChunk, num - start);
      for (int e = 0; e < count; ++e) {
        const int k = start + e;
        const auto& G = term.shape_gradients(k);
        const auto& vertices = term.element_vertices(k);
        g.setZero();
        for (int a = 0; a < kNodes; ++a)
          for (int i = 0; i < Dim; ++i)
            for (int b = 0; b < Dim; ++b)
              g.row(i + Dim * b) += G(a, b) * basis_t.col(Dim * vertices[a] + i).transpose();
        // Strain weights: Psi = 1/2 e^T W e, e = (E_00, .., E_dd, E_01, ..), off-diagonals counted twice.
        const LameParameters lame = term.element_lame(p, k);
        Eigen::Matrix<double, kComponents, kComponents> W =
            Eigen::Matrix<double, kComponents, kComponents>::Zero();
        W.template topLeftCorner<Dim, Dim>().setConstant(lame.lambda);
        for (int c = 0; c < kComponents; ++c) W(c, c) += (c < Dim ? 2.0 : 4.0) * lame.mu;
        W *= term.rest_volume(k);
        const Eigen::Matrix<double, kComponents, kComponents> Lw = W.llt().matrixL();
        Eigen::Matrix<double, Eigen::Dynamic, kComponents> linear(r, kComponents);
        Eigen::Matrix<double, Eigen::Dynamic, kComponents> quadratic(num_pairs, kComponents);
        for (int c = 0; c < kComponents; ++c) {
          const int a = comp_a[c], b = comp_b[c];
          linear.col(c) = 0.5 * (g.row(a + Dim * b) + g.row(b + Dim * a)).transpose();
          // N_ab = sum_i (grad u)_ia (grad u)_ib = q^T outer q; packed on the pairs s.
          outer.noalias() = g.row(Dim * a).transpose() * g.row(Dim * b);
          for (int i = 1; i < Dim; ++i)
            outer.noalias() += g.row(i + Dim * a).transpose() * g.row(i + Dim * b);
          for (int s = 0; s < r; ++s) {
            quadratic(pair[static_cast<std::size_t>(s * r + s)], c) = outer(s, s);
            for (int t = s + 1; t < r; ++t)
              quadratic(pair[static_cast<std::size_t>(s * r + t)], c) = outer(s, t) + outer(t, s);
          }
        }
        y.block(0, kComponents * e, r, kComponents).noalias() = linear * Lw;
        y.block(r, kComponents * e, num_pairs, kComponents).noalias() = 0.5 * quadratic * Lw;
      }
      local.selfadjointView<Eigen::Lower>().rankUpdate(y.leftCols(kComponents * count));
    }
#pragma omp critical
    gram.triangularView<Eigen::Lower>() += local;
  }
}

}  // namespace

ReducedStvk::ReducedStvk(const Model& model, const Vector& p, const Matrix& basis) {
  const auto begin = std::chrono::steady_clock::now();
  if (basis.rows() != model.num_dofs())
    throw std::invalid_argument("ReducedStvk: the basis has " + std::to_string(basis.rows()) +
                                " rows, the model " + std::to_string(model.num_dofs()) + " DOFs");
  r_ = static_cast<int>(basis.cols());
  if (r_ < 1) throw std::invalid_argument("ReducedStvk: empty basis");
  pairs_ = r_ * (r_ + 1) / 2;
  pair_.assign(static_cast<std::size_t>(r_) * r_, 0);
  for (int a = 0, k = 0; a < r_; ++a)
    for (int b = a; b < r_; ++b, ++k)
      pair_[static_cast<std::size_t>(a * r_ + b)] = pair_[static_cast<std::size_t>(b * r_ + a)] = k;
  gram_ = Matrix::Zero(r_ + pairs_, r_ + pairs_);
  const Matrix basis_t = basis.transpose();
  int elastic_terms = 0;
  for (const auto& term : model.terms()) {
    if (const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(term.get())) {
      if (t3->material().name() != "stvk")
        throw std::invalid_argument("ReducedStvk: term '" + term->name() + "' is not StVK");
      accumulate<3>(*t3, p, basis_t, pair_, gram_);
      ++elastic_terms;
    } else if (const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(term.get())) {
      if (t2->material().name() != "stvk")
        throw std::invalid_argument("ReducedStvk: term '" + term->name() + "' is not StVK");
      accumulate<2>(*t2, p, basis_t, pair_, gram_);
      ++elastic_terms;
    }
  }
  if (elastic_terms == 0) throw std::invalid_argument("ReducedStvk: the model has no elastic term");
  gram_.triangularView<Eigen::StrictlyUpper>() = gram_.transpose();
#ifdef _OPENMP
  threads_ = omp_get_max_threads();
#endif
  precomputation_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

void ReducedStvk::evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const {
  if (q.size() != r_)
    throw std::invalid_argument("ReducedStvk: q has " + std::to_string(q.size()) + " entries, expected " +
                                std::to_string(r_));
  const int r = r_, P = pairs_;
  Vector w(r + P);
  w.head(r) = q;
  for (int a = 0, k = r; a < r; ++a)
    for (int b = a; b < r; ++b, ++k) w[k] = q[a] * q[b];
  // Symmetric product: reads the lower triangle only (the coefficients dominate the memory
  // traffic of an evaluation).
  const Vector y = gram_.selfadjointView<Eigen::Lower>() * w;
  if (energy) *energy = 0.5 * w.dot(y);
  // J_s^T v for v on the pairs: d/dq of sum_p v_p s_p at fixed v.
  const auto pairs_transpose = [&](const auto& v, auto&& out) {
    for (int a = 0, k = 0; a < r; ++a) {
      out[a] += 2.0 * v[k] * q[a];
      ++k;
      for (int b = a + 1; b < r; ++b, ++k) {
        out[a] += v[k] * q[b];
        out[b] += v[k] * q[a];
      }
    }
  };
  if (force) {
    *force = y.head(r);
    pairs_transpose(y.tail(P), *force);
  }
  if (stiffness) {
    // Hessian of 1/2 w^T G w with w = [q; s(q)], G = [[A, B], [B^T, D]]:
    //   A + B J_s + (B J_s)^T + J_s^T D J_s + sum_p y_p d2 s_p / dq2.
    // J_s^T D J_s = X + X^T - J_s^T diag(D) J_s with X = J_s^T (L J_s), L the lower triangle of
    // D (diagonal included): only the lower half of D is read, half the work of D J_s. A pair
    // p = (a, b) has d s_p / dq_b = q_a and d s_p / dq_a = q_b (2 q_a when a = b).
    Matrix lower_j = Matrix::Zero(P, r), b_j = Matrix::Zero(r, r);
    for (int a = 0, p = 0; a < r; ++a)
      for (int b = a; b < r; ++b, ++p) {
        const auto column = gram_.col(r + p);
        const auto lower = column.segment(r + p, P - p);
        if (a == b) {
          lower_j.col(a).tail(P - p).noalias() += (2.0 * q[a]) * lower;
          b_j.col(a).noalias() += (2.0 * q[a]) * column.head(r);
        } else {
          lower_j.col(b).tail(P - p).noalias() += q[a] * lower;
          lower_j.col(a).tail(P - p).noalias() += q[b] * lower;
          b_j.col(b).noalias() += q[a] * column.head(r);
          b_j.col(a).noalias() += q[b] * column.head(r);
        }
      }
    Matrix x = Matrix::Zero(r, r);
    for (int c = 0; c < r; ++c) pairs_transpose(lower_j.col(c), x.col(c));
    Matrix& K = *stiffness;
    K = gram_.topLeftCorner(r, r) + b_j + b_j.transpose() + x + x.transpose();
    for (int a = 0, k = r; a < r; ++a) {
      // - J_s^T diag(D) J_s, + sum_p y_p d2 s_p / dq2
      const double d_aa = gram_(k, k);
      K(a, a) += 2.0 * y[k] - 4.0 * d_aa * q[a] * q[a];
      ++k;
      for (int b = a + 1; b < r; ++b, ++k) {
        const double d = gram_(k, k);
        K(a, a) -= d * q[b] * q[b];
        K(b, b) -= d * q[a] * q[a];
        const double off = y[k] - d * q[a] * q[b];
        K(a, b) += off;
        K(b, a) += off;
      }
    }
  }
}

}  // namespace tailor
