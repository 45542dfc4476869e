#include "forward/reduction/cubature.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "forward/reduction/nnls.hpp"

namespace tailor {

CubatureTraining cubature_training(const SubspaceElements& elements, const std::vector<Vector>& poses,
                                   const Matrix& element_weights) {
  const int r = elements.reduced_size(), n = elements.size();
  const int blocks = static_cast<int>(element_weights.cols());
  if (blocks < 1) throw std::invalid_argument("cubature_training: no weight column");
  std::vector<Matrix> kept;
  CubatureTraining t;
  Vector f(r);
  for (const Vector& q : poses) {
    if (q.size() != r) throw std::invalid_argument("cubature_training: a pose has the wrong size");
    Matrix block(blocks * r, n);
    bool usable = true;
    for (int k = 0; k < n && usable; ++k) {
      f.setZero();
      usable = elements.add(k, q, 1.0, nullptr, &f, nullptr);
      const int e = elements.mesh_element(k);
      if (e >= element_weights.rows())
        throw std::invalid_argument("cubature_training: the weights have " + std::to_string(element_weights.rows()) +
                                    " rows, element " + std::to_string(e) + " is covered");
      for (int c = 0; c < blocks; ++c) block.block(c * r, k, r, 1) = element_weights(e, c) * f;
    }
    const double scale = usable ? block.topRows(r).rowwise().sum().norm() : 0.0;
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      ++t.skipped_poses;
      continue;
    }
    kept.push_back(block / scale);
  }
  if (kept.empty()) throw std::invalid_argument("cubature_training: no usable training pose (all at rest or inverted)");
  t.poses = static_cast<int>(kept.size());
  t.a.resize(static_cast<Eigen::Index>(kept.size()) * blocks * r, n);
  for (std::size_t p = 0; p < kept.size(); ++p)
    t.a.middleRows(static_cast<Eigen::Index>(p) * blocks * r, blocks * r) = kept[p];
  t.b = t.a.rowwise().sum();
  return t;
}

CubatureRule fit_cubature(const Matrix& a, const Vector& b, const CubatureOptions& options) {
  if (options.max_elements < 1)
    throw std::invalid_argument("fit_cubature: at least one element is needed, got " +
                                std::to_string(options.max_elements));
  if (!(options.tolerance > 0.0)) throw std::invalid_argument("fit_cubature: the tolerance must be positive");
  if (options.candidates < 0)
    throw std::invalid_argument("fit_cubature: candidates must be >= 0 (0: every element), got " +
                                std::to_string(options.candidates));
  if (b.size() != a.rows()) throw std::invalid_argument("fit_cubature: b and A differ in rows");
  const double b_norm = b.norm();
  if (!(b_norm > 0.0)) throw std::invalid_argument("fit_cubature: nothing to integrate (b = 0)");
  const Eigen::Index n = a.cols();
  const Vector column_norms = a.colwise().norm().transpose();
  CubatureRule rule;
  std::vector<bool> chosen(static_cast<std::size_t>(n), false);
  Vector residual = b;
  Vector weights;  // on rule.elements
  const int limit = static_cast<int>(std::min<Eigen::Index>(options.max_elements, n));
  std::mt19937_64 random(options.seed);
  std::vector<Eigen::Index> pool;  // the unchosen elements with a nonzero column
  rule.training_error = 1.0;
  // Each step adds one element; NNLS may drop some, so the steps are bounded separately.
  for (int step = 0; step < 4 * limit + 10 && static_cast<int>(rule.elements.size()) < limit; ++step) {
    if (rule.training_error <= options.tolerance) break;
    // The element whose column points most along the residual (positive weights only), among
    // every unchosen element or a random subset of them.
    pool.clear();
    for (Eigen::Index k = 0; k < n; ++k)
      if (!chosen[static_cast<std::size_t>(k)] && column_norms[k] > 0.0) pool.push_back(k);
    std::size_t scored = pool.size();
    if (options.candidates > 0 && pool.size() > static_cast<std::size_t>(options.candidates)) {
      scored = static_cast<std::size_t>(options.candidates);
      for (std::size_t i = 0; i < scored; ++i)  // the first `scored` of a Fisher-Yates shuffle
        std::swap(pool[i], pool[std::uniform_int_distribution<std::size_t>(i, pool.size() - 1)(random)]);
    }
    Eigen::Index best = -1;
    double best_value = 0.0;
    if (scored == pool.size()) {
      const Vector score = a.transpose() * residual;
      for (const Eigen::Index k : pool)
        if (const double s = score[k] / column_norms[k]; s > best_value) best_value = s, best = k;
    } else {
      // When no candidate of the subset reduces the residual, the others are scored too.
      for (std::size_t i = 0; i < pool.size() && (i < scored || best < 0); ++i) {
        const Eigen::Index k = pool[i];
        if (const double s = a.col(k).dot(residual) / column_norms[k]; s > best_value)
          best_value = s, best = k;
      }
    }
    if (best < 0) break;  // no element reduces the residual
    ++rule.steps;
    chosen[static_cast<std::size_t>(best)] = true;
    rule.elements.push_back(static_cast<int>(best));
    Matrix sub(a.rows(), static_cast<Eigen::Index>(rule.elements.size()));
    for (std::size_t c = 0; c < rule.elements.size(); ++c) sub.col(static_cast<Eigen::Index>(c)) = a.col(rule.elements[c]);
    Vector start = Vector::Zero(sub.cols());
    start.head(weights.size()) = weights;
    const NnlsResult fit = nnls(sub, b, 0, &start);
    // Keep the elements with positive weight.
    std::vector<int> elements;
    std::vector<double> kept;
    for (std::size_t c = 0; c < rule.elements.size(); ++c) {
      const double v = fit.x[static_cast<Eigen::Index>(c)];
      if (v > 0.0) {
        elements.push_back(rule.elements[c]);
        kept.push_back(v);
      } else {
        chosen[static_cast<std::size_t>(rule.elements[c])] = c + 1 == rule.elements.size();  // not again at once
      }
    }
    rule.elements = std::move(elements);
    weights = Eigen::Map<const Vector>(kept.data(), static_cast<Eigen::Index>(kept.size()));
    residual = b;
    for (std::size_t c = 0; c < rule.elements.size(); ++c)
      residual.noalias() -= weights[static_cast<Eigen::Index>(c)] * a.col(rule.elements[c]);
    rule.training_error = residual.norm() / b_norm;
  }
  rule.weights = weights;
  return rule;
}

}  // namespace tailor
