// p_i = s_i z_i: design variables in units of a characteristic size (e.g. displacements in
// units of the expected displacement, so they are O(1) like log-moduli and the optimizer sees a
// well-scaled problem).
#include <cmath>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

class ScaleMap final : public detail::CheckedMap {
 public:
  explicit ScaleMap(Vector scales) : scales_(std::move(scales)) {}
  std::string name() const override { return concat("scale(", scales_.size(), ")"); }
  int num_design() const override { return static_cast<int>(scales_.size()); }
  int num_params() const override { return static_cast<int>(scales_.size()); }

 protected:
  Vector do_apply(const Vector& z) const override { return scales_.cwiseProduct(z); }
  Vector do_jacobian_times(const Vector&, const Vector& dz) const override {
    return scales_.cwiseProduct(dz);
  }
  Vector do_jacobian_transpose_times(const Vector&, const Vector& w) const override {
    return scales_.cwiseProduct(w);
  }

 private:
  Vector scales_;
};

}  // namespace

ParameterizationPtr scale_map(Vector scales) {
  for (Eigen::Index i = 0; i < scales.size(); ++i)
    if (!std::isfinite(scales[i]) || scales[i] == 0.0)
      detail::invalid_parameterization("scale_map",
                                       concat("scale ", i, " must be finite and non-zero, got ", scales[i]));
  return std::make_shared<ScaleMap>(std::move(scales));
}

}  // namespace tailor
