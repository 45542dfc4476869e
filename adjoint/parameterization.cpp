#include "adjoint/parameterization.hpp"

#include <stdexcept>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {

Vector Parameterization::second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const {
  // A map that does not override this declares itself linear in z: d/dz (J^T w) = 0. The
  // sizes are still checked so that a caller's mistake is not hidden behind a zero.
  detail::require_size(*this, "z", z, num_design(), "num_design");
  detail::require_size(*this, "w", w, num_params(), "num_params");
  detail::require_size(*this, "dz", dz, num_design(), "num_design");
  return Vector::Zero(num_design());
}

Matrix Parameterization::jacobian(const Vector& z) const {
  // Column by column from the direct-mode product: O(num_design) products, meant for tests
  // and small problems. Building it from jacobian_times (not the transpose) keeps the
  // dot-product test between the two products meaningful for code that uses this matrix.
  detail::require_size(*this, "z", z, num_design(), "num_design");
  Matrix J(num_params(), num_design());
  Vector unit = Vector::Zero(num_design());
  for (int j = 0; j < num_design(); ++j) {
    unit[j] = 1.0;
    J.col(j) = jacobian_times(z, unit);
    unit[j] = 0.0;
  }
  return J;
}

namespace detail {

void invalid_parameterization(const std::string& where, const std::string& what) {
  throw std::invalid_argument(where + ": " + what);
}

void require_size(const Parameterization& map, const char* argument, const Vector& v, Eigen::Index expected,
                  const char* expected_role) {
  if (v.size() != expected)
    invalid_parameterization(
        map.name(), concat(argument, " has size ", v.size(), ", expected ", expected_role, " = ", expected));
}

Vector CheckedMap::apply(const Vector& z) const {
  require_size(*this, "z", z, num_design(), "num_design");
  return do_apply(z);
}

Vector CheckedMap::jacobian_times(const Vector& z, const Vector& dz) const {
  require_size(*this, "z", z, num_design(), "num_design");
  require_size(*this, "dz", dz, num_design(), "num_design");
  return do_jacobian_times(z, dz);
}

Vector CheckedMap::jacobian_transpose_times(const Vector& z, const Vector& w) const {
  require_size(*this, "z", z, num_design(), "num_design");
  require_size(*this, "w", w, num_params(), "num_params");
  return do_jacobian_transpose_times(z, w);
}

Vector CheckedMap::second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const {
  require_size(*this, "z", z, num_design(), "num_design");
  require_size(*this, "w", w, num_params(), "num_params");
  require_size(*this, "dz", dz, num_design(), "num_design");
  return do_second_derivative_times(z, w, dz);
}

Vector CheckedMap::do_second_derivative_times(const Vector&, const Vector&, const Vector&) const {
  return Vector::Zero(num_design());
}

}  // namespace detail
}  // namespace tailor
