#pragma once
// Shared plumbing for the concrete parameterizations (internal; not part of the public API).
// Argument sizes are checked once, here, so every map implements only its mathematics and all
// of them report a wrong-sized z, w or dz the same way: naming the map and both sizes.
#include <sstream>
#include <string>

#include "adjoint/parameterization.hpp"

namespace tailor::detail {

// Throws std::invalid_argument("<where>: <what>").
[[noreturn]] void invalid_parameterization(const std::string& where, const std::string& what);

// Throws unless v.size() == expected, e.g. "exp(12): dz has size 3, expected num_design = 12".
void require_size(const Parameterization& map, const char* argument, const Vector& v, Eigen::Index expected,
                  const char* expected_role);

// Streams its arguments into a string (for messages and names).
template <typename... Args>
std::string concat(const Args&... args) {
  std::ostringstream s;
  (s << ... << args);
  return s.str();
}

class CheckedMap : public Parameterization {
 public:
  Vector apply(const Vector& z) const final;
  Vector jacobian_times(const Vector& z, const Vector& dz) const final;
  Vector jacobian_transpose_times(const Vector& z, const Vector& w) const final;
  Vector second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const final;

 protected:
  // Called with arguments of the right sizes only.
  virtual Vector do_apply(const Vector& z) const = 0;
  virtual Vector do_jacobian_times(const Vector& z, const Vector& dz) const = 0;
  virtual Vector do_jacobian_transpose_times(const Vector& z, const Vector& w) const = 0;
  // Default: zero, correct for maps linear in z (their Jacobian does not depend on z).
  virtual Vector do_second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const;
};

}  // namespace tailor::detail
