#include "forward/reduction/krylov_recurrence.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "forward/reduction/free_stiffness_factor.hpp"

namespace tailor {
namespace {

using Multiset = std::vector<int>;

// Sorted multisets of size j drawn from {0..r-1}, in lexicographic order.
std::vector<Multiset> sorted_multisets(int r, int j) {
  std::vector<Multiset> out;
  Multiset a(j, 0);
  while (true) {
    out.push_back(a);
    int i = j - 1;
    while (i >= 0 && a[i] == r - 1) --i;
    if (i < 0) break;
    ++a[i];
    for (int t = i + 1; t < j; ++t) a[t] = a[i];
  }
  return out;
}

void enumerate_partitions(int j, int slot, std::vector<std::vector<int>>& blocks,
                          std::vector<std::vector<std::vector<int>>>& out) {
  if (slot == j) {
    if (blocks.size() >= 2) out.push_back(blocks);
    return;
  }
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    blocks[b].push_back(slot);
    enumerate_partitions(j, slot + 1, blocks, out);
    blocks[b].pop_back();
  }
  blocks.push_back({slot});
  enumerate_partitions(j, slot + 1, blocks, out);
  blocks.pop_back();
}

}  // namespace

std::vector<std::vector<std::vector<int>>> nontrivial_partitions(int j) {
  std::vector<std::vector<std::vector<int>>> out;
  std::vector<std::vector<int>> blocks;
  if (j >= 2) enumerate_partitions(j, 0, blocks, out);
  return out;
}

Vector force_derivative(const Model& model, const Vector& x, const Vector& p, const std::vector<Vector>& directions,
                        double step) {
  if (directions.empty()) throw std::invalid_argument("force_derivative: needs at least one direction");
  if (directions.size() == 1) return model.hessian_times(x, p, directions[0]);
  const Vector& last = directions.back();
  const double largest = last.cwiseAbs().maxCoeff();
  if (!(step > 0.0)) throw std::invalid_argument("force_derivative: step must be > 0");
  if (!(largest > 0.0)) return Vector::Zero(x.size());  // multilinear: a zero direction gives zero
  const double e = step / largest;
  const std::vector<Vector> rest(directions.begin(), directions.end() - 1);
  return (force_derivative(model, x + e * last, p, rest, step) - force_derivative(model, x - e * last, p, rest, step)) /
         (2.0 * e);
}

Matrix KrylovRecurrence::all() const {
  Eigen::Index cols = 0, rows = blocks.empty() ? 0 : blocks.front().rows();
  for (const Matrix& b : blocks) cols += b.cols();
  for (const Matrix& b : inertia) cols += b.cols();
  Matrix out(rows, cols);
  Eigen::Index c = 0;
  for (const auto* list : {&blocks, &inertia})
    for (const Matrix& b : *list) {
      out.middleCols(c, b.cols()) = b;
      c += b.cols();
    }
  return out;
}

KrylovRecurrence krylov_recurrence(const Model& model, const Vector& x, const Vector& p, const SparseMatrix& mass,
                                   const Matrix& start, const KrylovRecurrenceOptions& options) {
  const int n = model.num_dofs();
  if (x.size() != n || start.rows() != n || mass.rows() != n || mass.cols() != n)
    throw std::invalid_argument("krylov_recurrence: state, start vectors and mass need " + std::to_string(n) +
                                " rows");
  if (options.order < 1 || options.order > 6)
    throw std::invalid_argument("krylov_recurrence: order must be in [1, 6], got " + std::to_string(options.order));
  if (start.cols() < 1) throw std::invalid_argument("krylov_recurrence: needs at least one start vector");
  double step = options.step;
  if (step == 0.0) step = 1e-3 * std::max(x.maxCoeff() - x.minCoeff(), 1e-300);
  if (!(step > 0.0)) throw std::invalid_argument("krylov_recurrence: step must be > 0 (or 0 for the default)");

  const FreeStiffnessFactor stiffness(model, x, p);
  const int r = static_cast<int>(start.cols());
  KrylovRecurrence out;
  std::map<Multiset, Vector> response;  // U(a) for every multiset computed so far
  out.blocks.push_back(start);
  out.slots.emplace_back();
  for (int a = 0; a < r; ++a) {
    out.slots[0].push_back({a});
    response[{a}] = start.col(a);
  }
  for (int j = 2; j <= options.order; ++j) {
    const std::vector<Multiset> multisets = sorted_multisets(r, j);
    const auto partitions = nontrivial_partitions(j);
    Matrix rhs(n, static_cast<Eigen::Index>(multisets.size()));
    for (std::size_t c = 0; c < multisets.size(); ++c) {
      const Multiset& a = multisets[c];
      // F is symmetric in its arguments: partitions giving the same multiset of sub-multisets
      // contribute the same term, evaluated once with its count.
      std::map<std::vector<Multiset>, int> terms;
      for (const auto& partition : partitions) {
        std::vector<Multiset> parts;
        for (const auto& block : partition) {
          Multiset sub;
          for (int slot : block) sub.push_back(a[slot]);
          std::sort(sub.begin(), sub.end());
          parts.push_back(sub);
        }
        std::sort(parts.begin(), parts.end());
        ++terms[parts];
      }
      Vector sum = Vector::Zero(n);
      for (const auto& [parts, count] : terms) {
        std::vector<Vector> directions;
        for (const Multiset& sub : parts) directions.push_back(response.at(sub));
        sum += count * force_derivative(model, x, p, directions, step);
        ++out.force_derivative_evaluations;
      }
      rhs.col(static_cast<Eigen::Index>(c)) = -sum;
    }
    Matrix block = stiffness.solve(rhs);
    for (std::size_t c = 0; c < multisets.size(); ++c)
      response[multisets[c]] = block.col(static_cast<Eigen::Index>(c));
    out.blocks.push_back(std::move(block));
    out.slots.push_back(multisets);
  }
  if (options.inertia_blocks)
    for (const Matrix& b : out.blocks) {
      Matrix inertia = stiffness.solve(mass * b);
      for (Eigen::Index c = 0; c < inertia.cols(); ++c) {
        const double norm = std::sqrt(std::max(inertia.col(c).dot(mass * inertia.col(c)), 0.0));
        if (norm > 0.0) inertia.col(c) /= norm;
      }
      out.inertia.push_back(std::move(inertia));
    }
  return out;
}

}  // namespace tailor
