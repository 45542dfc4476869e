// Combinators: composition p = outer(inner(z)), and embedding of designed blocks into a fixed
// base parameter vector.
#include <algorithm>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

// With q = inner(z), J = J_o(q) J_i(z), and the second-order term follows from
// d/dz [J_i^T J_o^T w] dz = (d/dz J_i^T)[J_o^T w] dz + J_i^T (d/dq J_o^T w)(J_i dz):
//   inner.second(z, J_o^T w, dz) + J_i^T outer.second(q, w, J_i dz).
class ComposedMap final : public detail::CheckedMap {
 public:
  ComposedMap(ParameterizationPtr outer, ParameterizationPtr inner)
      : outer_(std::move(outer)), inner_(std::move(inner)) {}
  std::string name() const override { return concat("compose(", outer_->name(), ", ", inner_->name(), ")"); }
  int num_design() const override { return inner_->num_design(); }
  int num_params() const override { return outer_->num_params(); }

 protected:
  Vector do_apply(const Vector& z) const override { return outer_->apply(inner_->apply(z)); }
  Vector do_jacobian_times(const Vector& z, const Vector& dz) const override {
    return outer_->jacobian_times(inner_->apply(z), inner_->jacobian_times(z, dz));
  }
  Vector do_jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    return inner_->jacobian_transpose_times(z, outer_->jacobian_transpose_times(inner_->apply(z), w));
  }
  Vector do_second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const override {
    const Vector q = inner_->apply(z);
    const Vector outer_weights = outer_->jacobian_transpose_times(q, w);
    const Vector outer_second = outer_->second_derivative_times(q, w, inner_->jacobian_times(z, dz));
    return inner_->second_derivative_times(z, outer_weights, dz) +
           inner_->jacobian_transpose_times(z, outer_second);
  }

 private:
  ParameterizationPtr outer_, inner_;
};

// p = base with p[offset_k, offset_k + size_k) = block_k(z_k), z = [z_1, z_2, ...]. The
// Jacobian is block diagonal on the designed ranges and zero on the fixed entries, so every
// product works block by block.
class EmbeddedBlocks final : public detail::CheckedMap {
 public:
  EmbeddedBlocks(Vector base, std::vector<ParameterBlock> blocks)
      : base_(std::move(base)), blocks_(std::move(blocks)) {
    for (const auto& b : blocks_) {
      design_offsets_.push_back(num_design_);
      num_design_ += b.map->num_design();
    }
  }
  std::string name() const override {
    std::string s = concat("embed_blocks(", base_.size());
    for (std::size_t k = 0; k < blocks_.size(); ++k) {
      const auto& b = blocks_[k];
      s += concat(k == 0 ? ": " : ", ", "[", b.offset, ", ", b.offset + b.map->num_params(), ") <- ",
                  b.map->name());
    }
    return s + ")";
  }
  int num_design() const override { return num_design_; }
  int num_params() const override { return static_cast<int>(base_.size()); }

 private:
  // Block k's slice of a design-sized (z, dz, J^T w) or parameter-sized (p, w) vector.
  template <typename V>
  auto design_of(std::size_t k, V& v) const {
    return v.segment(design_offsets_[k], blocks_[k].map->num_design());
  }
  template <typename V>
  auto params_of(std::size_t k, V& v) const {
    return v.segment(blocks_[k].offset, blocks_[k].map->num_params());
  }

 protected:
  Vector do_apply(const Vector& z) const override {
    Vector p = base_;
    for (std::size_t k = 0; k < blocks_.size(); ++k) params_of(k, p) = blocks_[k].map->apply(design_of(k, z));
    return p;
  }
  Vector do_jacobian_times(const Vector& z, const Vector& dz) const override {
    Vector dp = Vector::Zero(base_.size());
    for (std::size_t k = 0; k < blocks_.size(); ++k)
      params_of(k, dp) = blocks_[k].map->jacobian_times(design_of(k, z), design_of(k, dz));
    return dp;
  }
  Vector do_jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    Vector out(num_design_);
    for (std::size_t k = 0; k < blocks_.size(); ++k)
      design_of(k, out) = blocks_[k].map->jacobian_transpose_times(design_of(k, z), params_of(k, w));
    return out;
  }
  Vector do_second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const override {
    Vector out(num_design_);
    for (std::size_t k = 0; k < blocks_.size(); ++k)
      design_of(k, out) =
          blocks_[k].map->second_derivative_times(design_of(k, z), params_of(k, w), design_of(k, dz));
    return out;
  }

 private:
  Vector base_;
  std::vector<ParameterBlock> blocks_;
  std::vector<int> design_offsets_;  // where block k's design variables start in z
  int num_design_ = 0;
};

}  // namespace

ParameterizationPtr compose(ParameterizationPtr outer, ParameterizationPtr inner) {
  if (!outer || !inner)
    detail::invalid_parameterization("compose", outer ? "inner map is null" : "outer map is null");
  if (outer->num_design() != inner->num_params())
    detail::invalid_parameterization(
        "compose", concat("size mismatch: inner map ", inner->name(), " produces ", inner->num_params(),
                          " parameters but outer map ", outer->name(), " takes ", outer->num_design()));
  return std::make_shared<ComposedMap>(std::move(outer), std::move(inner));
}

ParameterizationPtr embed_blocks(Vector base, std::vector<ParameterBlock> blocks) {
  std::vector<std::size_t> order;  // non-empty blocks, for the overlap test
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const auto& b = blocks[k];
    if (!b.map) detail::invalid_parameterization("embed_blocks", concat("block ", k, " has a null map"));
    if (b.offset < 0 || b.offset + b.map->num_params() > base.size())
      detail::invalid_parameterization(
          "embed_blocks",
          concat("block ", k, " (", b.map->name(), ") covers [", b.offset, ", ",
                 b.offset + b.map->num_params(), "), outside the base vector of size ", base.size()));
    if (b.map->num_params() > 0) order.push_back(k);
  }
  // Overlap: after sorting by offset, each block must end before the next one starts (an empty
  // block replaces nothing, so it cannot overlap).
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return blocks[a].offset < blocks[b].offset; });
  for (std::size_t r = 1; r < order.size(); ++r) {
    const auto &prev = blocks[order[r - 1]], &next = blocks[order[r]];
    if (prev.offset + prev.map->num_params() > next.offset)
      detail::invalid_parameterization(
          "embed_blocks", concat("blocks ", order[r - 1], " [", prev.offset, ", ",
                                 prev.offset + prev.map->num_params(), ") and ", order[r], " [", next.offset,
                                 ", ", next.offset + next.map->num_params(), ") overlap"));
  }
  return std::make_shared<EmbeddedBlocks>(std::move(base), std::move(blocks));
}

}  // namespace tailor
