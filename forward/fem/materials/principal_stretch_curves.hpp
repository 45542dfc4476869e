#pragma once
// The three curves of a principal-stretch material (Xu, Sin, Zhu, Barbic 2015, Eq. 6, the
// separable Valanis-Landel extension):
//   Psi(l1, l2, l3) = sum_i f(l_i) + sum_{i<j} g(l_i l_j) + h(l1 l2 l3),
// with f the uniaxial, g the biaxial and h the volumetric curve, each a CubicSpline in its own
// argument (stretch, stretch product, volume ratio J), continued linearly outside its range.
// l_i are the signed singular values of F (rotation-variant SVD: only the smallest may be < 0),
// so the density is defined, and continued linearly, under inversion. Plane strain (Dim = 2)
// uses the 3D density with l3 = 1 pinned: Psi(l1, l2, 1) = f(l1) + f(l2) + f(1) + g(l1 l2) +
// g(l1) + g(l2) + h(l1 l2).
//
// Presets (lambda, mu the Lame parameters; every preset is stress free at rest and linear
// elastic to first order there):
//  - corotated (exact, the project's linear corotated mu sum (l-1)^2 + lambda/2 (sum l - 3)^2):
//      f(s) = (mu + lambda/2)(s - 1)^2 - 2 lambda s + lambda,  g(t) = lambda t,  h = 0.
//  - stvk (Psi = lambda/2 tr(E)^2 + mu |E|^2, E_i = (l_i^2 - 1)/2):
//      f(s) = lambda/8 (s^4 - 6 s^2 + 3) + mu/4 (s^2 - 1)^2,  g(t) = lambda/4 t^2,  h = 0;
//    g is exact, f is quartic: its quasi-interpolant differs by O(h^4 (3 lambda + 6 mu)) in value
//    and O(h^3) in slope (h the knot spacing; measured in the tests).
//  - neo_hookean: the project's stable Neo-Hookean (neo_hookean.hpp) is NOT separable, its
//    regulariser log(I_C + 1) = log(1 + sum l_i^2) couples the stretches. The preset is the
//    separable part of Smith, de Goes, Kim 2018 (their Neo-Hookean before the log term):
//      Psi = mu'/2 (I_C - 3) + lambda'/2 (J - alpha)^2 - lambda'/2 (1 - alpha)^2,
//      mu' = mu, lambda' = lambda + mu, alpha = 1 + mu/lambda'   (stress free, Lame (lambda, mu)),
//    i.e. f(s) = mu/2 (s^2 - 1), g = 0, h(J) = lambda'/2 ((J - alpha)^2 - (1 - alpha)^2): exact.
//    Near rest it agrees with the project's Neo-Hookean to first order (same Lame parameters).
#include <Eigen/Core>
#include <string>

#include "forward/fem/material.hpp"
#include "forward/fem/materials/cubic_spline.hpp"

namespace tailor {

// Uniform knots on [lower, upper] with `intervals` intervals (see CubicSpline).
struct SplineGrid {
  double lower;
  double upper;
  int intervals;
};

struct PrincipalStretchCurves {
  CubicSpline uniaxial;    // f(l_i)
  CubicSpline biaxial;     // g(l_i l_j)
  CubicSpline volumetric;  // h(l1 l2 l3)

  // Flat control vector [f controls; g controls; h controls].
  int num_controls() const;
  Eigen::VectorXd controls() const;
  void set_controls(const Eigen::Ref<const Eigen::VectorXd>& controls);  // throws on size mismatch
};

// Grids used by the presets by default: wide enough that the deformations of the tests
// (stretches in [-2, 4], inversion included) stay inside, fine enough for StVK's quartic f.
struct PrincipalStretchGrids {
  SplineGrid uniaxial{-2.0, 4.0, 60};
  SplineGrid biaxial{-4.0, 16.0, 50};
  SplineGrid volumetric{-8.0, 8.0, 32};
};

// Curves with all control values zero on the given grids.
PrincipalStretchCurves zero_curves(const PrincipalStretchGrids& grids);

enum class SplinePreset { corotated, stvk, neo_hookean };
PrincipalStretchCurves principal_stretch_preset(SplinePreset preset, const LameParameters& lame,
                                                const PrincipalStretchGrids& grids = {});
// Names: "corotated", "stvk", "neo_hookean"; throws std::invalid_argument otherwise.
SplinePreset parse_spline_preset(const std::string& name);

}  // namespace tailor
