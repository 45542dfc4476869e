// p = basis z + offset, e.g. a few smooth material modes spanning the element moduli.
#include <cmath>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

// Linear in z: both products use the given (dense) basis, and the second-order term is the
// inherited zero.
class LinearBasisMap final : public detail::CheckedMap {
 public:
  LinearBasisMap(Matrix basis, Vector offset) : basis_(std::move(basis)), offset_(std::move(offset)) {}
  std::string name() const override {
    return concat("linear_basis(", basis_.cols(), " -> ", basis_.rows(), ")");
  }
  int num_design() const override { return static_cast<int>(basis_.cols()); }
  int num_params() const override { return static_cast<int>(basis_.rows()); }

 protected:
  Vector do_apply(const Vector& z) const override { return basis_ * z + offset_; }
  Vector do_jacobian_times(const Vector&, const Vector& dz) const override { return basis_ * dz; }
  Vector do_jacobian_transpose_times(const Vector&, const Vector& w) const override {
    return basis_.transpose() * w;
  }

 private:
  Matrix basis_;  // num_params x num_design
  Vector offset_;
};

}  // namespace

ParameterizationPtr linear_basis_map(Matrix basis, Vector offset) {
  if (offset.size() != basis.rows())
    detail::invalid_parameterization(
        "linear_basis_map", concat("offset has size ", offset.size(), " but the basis has ", basis.rows(),
                                   " rows (one per parameter)"));
  if (!basis.allFinite())
    detail::invalid_parameterization("linear_basis_map", "basis has non-finite entries");
  if (!offset.allFinite())
    detail::invalid_parameterization("linear_basis_map", "offset has non-finite entries");
  return std::make_shared<LinearBasisMap>(std::move(basis), std::move(offset));
}

}  // namespace tailor
