#pragma once
// Shared helpers for the material tests: deformation cases, Lame settings and a central-difference
// convergence study that fails on wrong derivatives (relative error AND observed order ~2).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/fem/material.hpp"
#include "forward/fem/material_registry.hpp"

namespace tailor::test {

template <int Dim>
using Mat = Eigen::Matrix<double, Dim, Dim>;

// Every registered material (forward/fem/material_registry.hpp), so that a new one is tested
// without listing it.
inline const std::vector<MaterialKind>& all_kinds() {
  static const std::vector<MaterialKind> kinds = [] {
    std::vector<MaterialKind> out;
    for (const MaterialEntry* entry : registered_materials()) out.push_back(parse_material_kind(entry->name));
    return out;
  }();
  return kinds;
}
inline const std::vector<MaterialKind>& nonlinear_kinds() {
  static const std::vector<MaterialKind> kinds = [] {
    std::vector<MaterialKind> out;
    for (MaterialKind kind : all_kinds())
      if (!make_material<3>(kind)->tangent_is_constant()) out.push_back(kind);
    return out;
  }();
  return kinds;
}

// Young's modulus 3.7 (not 1, so that a missing factor cannot hide) and three Poisson ratios:
// moderate, nearly incompressible and very nearly incompressible (lambda/mu ~ 5000).
struct LameCase {
  std::string name;
  double youngs, poisson;
  LameParameters lame() const { return lame_from_young_poisson(youngs, poisson); }
};
inline std::vector<LameCase> lame_cases() {
  return {{"nu=0.3", 3.7, 0.3}, {"nu=0.49", 3.7, 0.49}, {"nu=0.4999", 3.7, 0.4999}};
}

template <int Dim>
Mat<Dim> rotation_from_angle_axis(double angle, const Eigen::Vector3d& axis) {
  if constexpr (Dim == 2) {
    Mat<2> R;
    R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    return R;
  } else {
    return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  }
}

template <int Dim>
Mat<Dim> random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  if constexpr (Dim == 2) {
    return rotation_from_angle_axis<2>(std::numbers::pi * u(rng), Eigen::Vector3d::UnitZ());
  } else {
    Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
    q.normalize();
    return q.toRotationMatrix();
  }
}

// Q1 diag(s) Q2 with random rotations: prescribed (signed) singular values.
template <int Dim>
Mat<Dim> with_singular_values(std::mt19937& rng, const Eigen::Matrix<double, Dim, 1>& s) {
  return random_rotation<Dim>(rng) * s.asDiagonal() * random_rotation<Dim>(rng);
}

template <int Dim>
struct DeformationCase {
  std::string name;
  Mat<Dim> F;
};

// The deformation gradients every derivative check runs on.
template <int Dim>
std::vector<DeformationCase<Dim>> deformation_cases() {
  std::mt19937 rng(20240 + Dim);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<DeformationCase<Dim>> cases;
  auto sv = [](std::initializer_list<double> values) {
    Eigen::Matrix<double, Dim, 1> s;
    int i = 0;
    for (double v : values)
      if (i < Dim) s(i++) = v;
    return s;
  };
  for (int r = 0; r < 2; ++r) {
    Mat<Dim> G;
    for (int j = 0; j < Dim; ++j)
      for (int i = 0; i < Dim; ++i) G(i, j) = u(rng);
    cases.push_back({"near_identity_" + std::to_string(r), Mat<Dim>::Identity() + 0.1 * G});
  }
  for (int r = 0; r < 2; ++r) {
    Mat<Dim> F;
    do {
      for (int j = 0; j < Dim; ++j)
        for (int i = 0; i < Dim; ++i) F(i, j) = 1.5 * u(rng);
    } while (F.determinant() < 0.3);
    cases.push_back({"large_random_" + std::to_string(r), F});
  }
  cases.push_back(
      {"large_stretch", with_singular_values<Dim>(rng, Dim == 3 ? sv({2.4, 1.3, 0.45}) : sv({2.4, 0.45}))});
  cases.push_back({"rotation_90_times_stretch",
                   rotation_from_angle_axis<Dim>(std::numbers::pi / 2, Eigen::Vector3d(1, 1, 1)) *
                       (Dim == 3 ? sv({1.3, 0.8, 1.1}) : sv({1.3, 0.8})).asDiagonal()});
  cases.push_back({"nearly_inverted_J~1e-3",
                   with_singular_values<Dim>(rng, Dim == 3 ? sv({1.1, 0.9, 1e-3}) : sv({1.1, 1e-3}))});
  cases.push_back(
      {"inverted", with_singular_values<Dim>(rng, Dim == 3 ? sv({1.2, 0.9, -0.4}) : sv({1.2, -0.5}))});
  cases.push_back({"inverted_stretched",
                   with_singular_values<Dim>(rng, Dim == 3 ? sv({1.5, 1.4, -1.0}) : sv({1.5, -1.2}))});
  return cases;
}

// Central-difference study: fd(h) is the central difference with step h, analytic the claimed
// derivative (both flattened). Steps h0, h0/2, h0/4, h0/8.
struct FdStudy {
  std::vector<double> steps, errors, reference_norms;
  double analytic_norm = 0.0;
};

inline FdStudy fd_study(const Eigen::VectorXd& analytic, const std::function<Eigen::VectorXd(double)>& fd,
                        double h0) {
  FdStudy s;
  s.analytic_norm = analytic.norm();
  for (int k = 0; k < 4; ++k) {
    const double h = h0 / std::pow(2.0, k);
    const Eigen::VectorXd d = fd(h);
    s.steps.push_back(h);
    s.errors.push_back((d - analytic).norm());
    s.reference_norms.push_back(d.norm());
  }
  return s;
}

// Passes when
//  - the reference (finite difference) is not tiny: |fd| > min_reference, so a derivative that
//    is (wrongly) zero can not pass because the reference happens to vanish;
//  - the relative error at the smallest step is below rel_tol;
//  - and either the error decays like h^2 (observed order in [1.7, 2.3] between the two largest
//    steps, where truncation dominates round-off), or the function is polynomial of degree <= 2
//    along every direction so central differences are exact: every relative error < 1e-7.
// A wrong derivative leaves an h-independent error: relative error O(1) or order ~0.
inline ::testing::AssertionResult fd_converges(const FdStudy& s, double min_reference,
                                               double rel_tol = 1e-4) {
  std::ostringstream log;
  log.precision(3);
  log << " |analytic| = " << s.analytic_norm << ";";
  for (std::size_t k = 0; k < s.steps.size(); ++k)
    log << " h=" << s.steps[k] << ": |fd|=" << s.reference_norms[k]
        << " rel.err=" << s.errors[k] / s.reference_norms[k];
  const double ref = s.reference_norms.back();
  if (!(ref > min_reference))
    return ::testing::AssertionFailure()
           << "reference too small (" << ref << " <= " << min_reference << ")" << log.str();
  const double rel_last = s.errors.back() / ref;
  if (!(rel_last < rel_tol))
    return ::testing::AssertionFailure() << "relative error " << rel_last << " >= " << rel_tol << log.str();
  const double rel_first = s.errors[0] / s.reference_norms[0];
  if (rel_first < 1e-7) {
    for (std::size_t k = 0; k < s.steps.size(); ++k)
      if (!(s.errors[k] / s.reference_norms[k] < 1e-7))
        return ::testing::AssertionFailure() << "inconsistent errors" << log.str();
    return ::testing::AssertionSuccess();
  }
  const double order = std::log2(s.errors[0] / s.errors[1]);
  if (!(order > 1.7 && order < 2.3))
    return ::testing::AssertionFailure() << "observed order " << order << " is not ~2" << log.str();
  return ::testing::AssertionSuccess();
}

template <int Dim>
Eigen::VectorXd flat(const Mat<Dim>& A) {
  return Eigen::Map<const Eigen::VectorXd>(A.data(), Dim * Dim);
}

// Minimum eigenvalue of a symmetric matrix.
template <class M>
double min_eigenvalue(const M& A) {
  return symmetric_eigenvalues(Eigen::MatrixXd(A))(0);
}

}  // namespace tailor::test
