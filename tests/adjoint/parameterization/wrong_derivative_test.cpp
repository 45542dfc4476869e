// The checks used throughout these tests must be able to fail: deliberately wrong derivatives
// are caught.
#include "map_checks.hpp"

namespace tailor::wrong_derivative_test {
namespace {

using testing::random_vector;

// Wraps a map and corrupts one product. Derives from Parameterization directly, so it also
// exercises the base-class defaults (second_derivative_times = 0, jacobian()).
class CorruptedMap final : public Parameterization {
 public:
  enum class Defect { none, transpose_sign, jacobian_scale, second_scale, no_second };
  CorruptedMap(ParameterizationPtr inner, Defect defect) : inner_(std::move(inner)), defect_(defect) {}
  std::string name() const override { return "corrupted " + inner_->name(); }
  int num_design() const override { return inner_->num_design(); }
  int num_params() const override { return inner_->num_params(); }
  Vector apply(const Vector& z) const override { return inner_->apply(z); }
  Vector jacobian_times(const Vector& z, const Vector& dz) const override {
    Vector out = inner_->jacobian_times(z, dz);
    if (defect_ == Defect::jacobian_scale) out *= 1.001;
    return out;
  }
  Vector jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    Vector out = inner_->jacobian_transpose_times(z, w);
    if (defect_ == Defect::transpose_sign) out[1] = -out[1];
    return out;
  }
  Vector second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const override {
    if (defect_ == Defect::no_second) return Parameterization::second_derivative_times(z, w, dz);
    Vector out = inner_->second_derivative_times(z, w, dz);
    if (defect_ == Defect::second_scale) out *= 1.001;
    return out;
  }

 private:
  ParameterizationPtr inner_;
  Defect defect_;
};

struct Fixture {
  ParameterizationPtr inner =
      compose(exp_map(6), bounds_map(Vector::Constant(6, -1.0), Vector::Constant(6, 1.0)));
  Vector z = random_vector(6, 1);
  CorruptedMap corrupted(CorruptedMap::Defect defect) const { return CorruptedMap(inner, defect); }
};

TEST(WrongDerivative, UncorruptedWrapperPassesEveryCheck) {
  Fixture f;
  const CorruptedMap map = f.corrupted(CorruptedMap::Defect::none);
  testing::expect_first_order_consistent(map, f.z, true);
  testing::expect_second_order_consistent(map, f.z);
}

TEST(WrongDerivative, TransposeSignErrorIsCaughtByTheDotProductTest) {
  Fixture f;
  const CorruptedMap map = f.corrupted(CorruptedMap::Defect::transpose_sign);
  EXPECT_GT(testing::dot_product_mismatch(map, f.z), 1e-3);
  // The direct-mode check alone cannot see it: that is why the dot-product test exists.
  EXPECT_TRUE(testing::check_jacobian(map, f.z).passed);
}

TEST(WrongDerivative, ScaledJacobianIsCaughtByDifferences) {
  Fixture f;
  const DerivativeCheck c = testing::check_jacobian(f.corrupted(CorruptedMap::Defect::jacobian_scale), f.z);
  EXPECT_FALSE(c.passed) << c.message;
  EXPECT_LT(c.observed_order, 0.5) << c.message;  // the error stalls instead of falling
}

TEST(WrongDerivative, WrongSecondDerivativeIsCaught) {
  Fixture f;
  const DerivativeCheck scaled =
      testing::check_second_derivative(f.corrupted(CorruptedMap::Defect::second_scale), f.z);
  EXPECT_FALSE(scaled.passed) << scaled.message;
  // A nonlinear map that forgets to override the (zero) default is caught as well.
  const DerivativeCheck missing =
      testing::check_second_derivative(f.corrupted(CorruptedMap::Defect::no_second), f.z);
  EXPECT_FALSE(missing.passed) << missing.message;
  EXPECT_FALSE(missing.vanishing) << missing.message;
}

TEST(BaseDefaults, JacobianColumnsAndSecondDerivativeSizeChecks) {
  Fixture f;
  const CorruptedMap map = f.corrupted(CorruptedMap::Defect::no_second);
  EXPECT_TRUE(map.jacobian(f.z).isApprox(f.inner->jacobian(f.z), 1e-15));
  const Vector w = random_vector(6, 2);
  EXPECT_TRUE((map.jacobian(f.z).transpose() * w).isApprox(map.jacobian_transpose_times(f.z, w), 1e-14));
  EXPECT_EQ(map.second_derivative_times(f.z, w, w), Vector::Zero(6));
  testing::expect_invalid([&] { map.second_derivative_times(f.z, Vector::Zero(5), w); },
                          {"corrupted compose(exp(6), bounds(6))", "w has size 5"});
}

}  // namespace
}  // namespace tailor::wrong_derivative_test
