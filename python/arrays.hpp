#pragma once
// NumPy views of Eigen storage without copies: the array's base is a capsule that keeps the
// C++ object holding the storage alive (a shared_ptr), so the array stays valid after the call
// that made it. The views are read-only: the numbers are a result, not an input.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <memory>

namespace tailor::python {

inline pybind11::capsule keep_alive(std::shared_ptr<const void> owner) {
  auto* kept = new std::shared_ptr<const void>(std::move(owner));
  return pybind11::capsule(kept, [](void* p) { delete static_cast<std::shared_ptr<const void>*>(p); });
}

inline pybind11::array read_only(pybind11::array a) {
  a.attr("setflags")(pybind11::arg("write") = false);
  return a;
}

// A vector (any Eigen column of doubles with contiguous storage).
template <class Derived>
pybind11::array view(const std::shared_ptr<const void>& owner, const Eigen::PlainObjectBase<Derived>& v) {
  static_assert(Derived::IsVectorAtCompileTime || !Derived::IsRowMajor, "column-major storage expected");
  if constexpr (Derived::IsVectorAtCompileTime) {
    return read_only(pybind11::array_t<typename Derived::Scalar>(
        {v.size()}, {sizeof(typename Derived::Scalar)}, v.data(), keep_alive(owner)));
  } else {
    const auto s = static_cast<pybind11::ssize_t>(sizeof(typename Derived::Scalar));
    return read_only(pybind11::array_t<typename Derived::Scalar>({v.rows(), v.cols()}, {s, s * v.rows()},
                                                                 v.data(), keep_alive(owner)));
  }
}

}  // namespace tailor::python
