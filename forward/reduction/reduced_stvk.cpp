#include "forward/reduction/reduced_stvk.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "forward/core/parallel_errors.hpp"
#include "forward/fem/elastic_term.hpp"

namespace tailor {
namespace {

// Adds the element columns Y_e of one elastic term to the lower triangle of gram.
// weights: empty (one matrix, every element with weight 1, symmetric rank-k updates) or one
// column per output matrix, one row per mesh element (grams[j] += sum_e weights(e, j) Y_e Y_e^T).
// quadratic = false (the linear material): the pair rows of Y_e are zero, so the energy is the
// quadratic form of the linear strain.
template <int Dim>
void accumulate(const ElasticTerm<Dim>& term, const Vector& p, const Matrix& basis_t,
                const std::vector<int>& pair, const Matrix& weights, bool quadratic_strain, bool with_pairs,
                std::vector<Matrix>& grams) {
  constexpr int kComponents = Dim * (Dim + 1) / 2;  // independent strain components
  constexpr int kNodes = Dim + 1;
  const int r = static_cast<int>(basis_t.rows());
  const int num_pairs = r * (r + 1) / 2, width = with_pairs ? r + num_pairs : r;
  const int num = static_cast<int>(term.elements().size());
  constexpr int kChunk = 128;
  // Component c <-> (a, b): the diagonal first, then the off-diagonal pairs.
  int comp_a[kComponents], comp_b[kComponents];
  for (int c = 0, k = Dim; c < Dim; ++c) {
    comp_a[c] = comp_b[c] = c;
    for (int d = c + 1; d < Dim; ++d, ++k) comp_a[k] = c, comp_b[k] = d;
  }

  const int sets = static_cast<int>(grams.size());
  const bool weighted = weights.size() > 0;
  FirstError errors;  // element_lame refuses parameters out of range
#pragma omp parallel
  {
    std::vector<Matrix> local(static_cast<std::size_t>(sets), Matrix::Zero(width, width));
    Matrix scaled;
    Matrix y(width, kComponents * kChunk);
    Matrix g(Dim * Dim, r);  // row i + Dim * b: d(grad u)_ib / dq
    Matrix outer(r, r);
#pragma omp for schedule(dynamic)
    for (int start = 0; start < num; start += kChunk) try {
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
          if (!with_pairs || !quadratic_strain) continue;
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
        if (with_pairs && quadratic_strain)
          y.block(r, kComponents * e, num_pairs, kComponents).noalias() = 0.5 * quadratic * Lw;
        else if (with_pairs)
          y.block(r, kComponents * e, num_pairs, kComponents).setZero();
      }
      const auto block = y.leftCols(kComponents * count);
      if (!weighted) {
        local[0].selfadjointView<Eigen::Lower>().rankUpdate(block);
        continue;
      }
      for (int j = 0; j < sets; ++j) {
        scaled = block;
        for (int e = 0; e < count; ++e)
          scaled.middleCols(kComponents * e, kComponents) *= weights(term.elements()[start + e], j);
        // Only the lower triangle is read later: the triangular product computes half the GEMM.
        local[static_cast<std::size_t>(j)].triangularView<Eigen::Lower>() += scaled * block.transpose();
      }
    } catch (...) {
      errors.capture(start);
    }
#pragma omp critical
    for (int j = 0; j < sets; ++j)
      grams[static_cast<std::size_t>(j)].triangularView<Eigen::Lower>() += local[static_cast<std::size_t>(j)];
  }
  errors.rethrow();
}

// Accumulates the lower triangles of grams from every elastic term; returns the number of
// elastic terms. allow_linear: the linear material is accepted too (without the pair part).
int accumulate_model(const Model& model, const Vector& p, const Matrix& basis, const Matrix& weights,
                     bool allow_linear, bool with_pairs, const char* who, std::vector<Matrix>& grams) {
  const int r = static_cast<int>(basis.cols());
  std::vector<int> pair(static_cast<std::size_t>(r) * r, 0);
  for (int a = 0, k = 0; a < r; ++a)
    for (int b = a; b < r; ++b, ++k)
      pair[static_cast<std::size_t>(a * r + b)] = pair[static_cast<std::size_t>(b * r + a)] = k;
  const Matrix basis_t = basis.transpose();
  int elastic_terms = 0;
  const auto material_ok = [&](const std::string& name, const std::string& term) {
    if (name == "stvk" || (allow_linear && name == "linear")) return name == "stvk";
    throw std::invalid_argument(std::string(who) + ": term '" + term + "' uses the material '" + name +
                                "'; the exact polynomial precomputation needs StVK" +
                                (allow_linear ? " or linear" : "") +
                                " (other materials need a cubature rule)");
  };
  for (const auto& term : model.terms()) {
    if (const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(term.get())) {
      const bool quadratic = material_ok(t3->material().name(), term->name());
      accumulate<3>(*t3, p, basis_t, pair, weights, quadratic, with_pairs, grams);
      ++elastic_terms;
    } else if (const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(term.get())) {
      const bool quadratic = material_ok(t2->material().name(), term->name());
      accumulate<2>(*t2, p, basis_t, pair, weights, quadratic, with_pairs, grams);
      ++elastic_terms;
    }
  }
  if (elastic_terms == 0) throw std::invalid_argument(std::string(who) + ": the model has no elastic term");
  for (Matrix& g : grams) g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
  return elastic_terms;
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
  std::vector<Matrix> grams{Matrix::Zero(r_ + pairs_, r_ + pairs_)};
  accumulate_model(model, p, basis, Matrix(), false, true, "ReducedStvk", grams);
  gram_ = std::move(grams[0]);
#ifdef _OPENMP
  threads_ = omp_get_max_threads();
#endif
  precomputation_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

std::vector<Matrix> reduced_stvk_coefficients(const Model& model, const Vector& p, const Matrix& basis,
                                              const Matrix& element_weights) {
  if (basis.rows() != model.num_dofs())
    throw std::invalid_argument("reduced_stvk_coefficients: the basis has " + std::to_string(basis.rows()) +
                                " rows, the model " + std::to_string(model.num_dofs()) + " DOFs");
  const int r = static_cast<int>(basis.cols());
  if (r < 1) throw std::invalid_argument("reduced_stvk_coefficients: empty basis");
  if (element_weights.cols() < 1) throw std::invalid_argument("reduced_stvk_coefficients: no weight column");
  for (const auto& term : model.terms()) {
    int top = -1;
    if (const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(term.get()))
      for (int e : t3->elements()) top = std::max(top, e);
    if (const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(term.get()))
      for (int e : t2->elements()) top = std::max(top, e);
    if (top >= element_weights.rows())
      throw std::invalid_argument("reduced_stvk_coefficients: the weights have " +
                                  std::to_string(element_weights.rows()) + " rows, term '" + term->name() +
                                  "' covers element " + std::to_string(top));
  }
  // Only linear materials: the pair part vanishes, so it is not computed (r x r matrices).
  bool any_stvk = false;
  for (const auto& term : model.terms()) {
    if (const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(term.get()))
      any_stvk = any_stvk || t3->material().name() != "linear";
    if (const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(term.get()))
      any_stvk = any_stvk || t2->material().name() != "linear";
  }
  const int width = any_stvk ? r + r * (r + 1) / 2 : r;
  std::vector<Matrix> grams(static_cast<std::size_t>(element_weights.cols()), Matrix::Zero(width, width));
  accumulate_model(model, p, basis, element_weights, true, any_stvk, "reduced_stvk_coefficients", grams);
  return grams;
}

void ReducedStvk::evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const {
  if (q.size() != r_)
    throw std::invalid_argument("ReducedStvk: q has " + std::to_string(q.size()) + " entries, expected " +
                                std::to_string(r_));
  evaluate_stvk_polynomial(gram_, q, energy, force, stiffness);
}

void evaluate_stvk_polynomial(const Matrix& gram_, const Vector& q, double* energy, Vector* force,
                              Matrix* stiffness) {
  const int r = static_cast<int>(q.size()), P = r * (r + 1) / 2;
  if (gram_.rows() != r + P || gram_.cols() != r + P)
    throw std::invalid_argument("evaluate_stvk_polynomial: the coefficients are " +
                                std::to_string(gram_.rows()) + " x " + std::to_string(gram_.cols()) +
                                ", q has " + std::to_string(r) +
                                " entries (expected r + r (r + 1) / 2 = " + std::to_string(r + P) + ")");
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
