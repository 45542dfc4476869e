#pragma once
// Hyperelastic materials: energy density Psi(F; lambda, mu) per unit rest volume, its first
// Piola-Kirchhoff stress P = dPsi/dF, the tangent dP/dF, and derivatives in the Lame
// parameters.
//
// Conventions
//  - Dim = 3: 3D. Dim = 2: plane strain, i.e. the 3D density evaluated at diag(F, 1).
//  - vec(F) is column-major: entry (i, j) of F is component i + Dim * j; the tangent is
//    d vec(P) / d vec(F) (Dim^2 x Dim^2).
//  - (lambda, mu) are always the physical Lame parameters of the small-strain response, so
//    every material agrees with linear elasticity to first order at F = I. A material that
//    needs other internal constants (e.g. stable Neo-Hookean) maps them itself.
#include <Eigen/Core>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

struct LameParameters {
  double lambda;
  double mu;
};

// Lame parameters from Young's modulus E > 0 and Poisson's ratio -1 < nu < 0.5 (3D and plane
// strain use the same formulas).
LameParameters lame_from_young_poisson(double youngs_modulus, double poisson_ratio);
// d(lambda, mu) / d(E, nu) as a 2x2 matrix: rows (lambda, mu), columns (E, nu).
Eigen::Matrix2d lame_jacobian(double youngs_modulus, double poisson_ratio);

template <int Dim>
struct MaterialEvaluation {
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  using Tangent = Eigen::Matrix<double, Dim * Dim, Dim * Dim>;
  double energy_density = 0.0;  // Psi
  Mat stress;                   // P = dPsi/dF
  Tangent tangent;              // dvec(P)/dvec(F)
};

template <int Dim>
struct MaterialLameDerivatives {
  Eigen::Vector2d energy_density;              // (dPsi/dlambda, dPsi/dmu)
  Eigen::Matrix<double, Dim * Dim, 2> stress;  // dvec(P)/d(lambda, mu)
};

template <int Dim>
class Material {
 public:
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  virtual ~Material() = default;
  virtual std::string name() const = 0;

  // Fills energy_density always, stress when want_stress, tangent when want_tangent. With
  // mode == projected the tangent is made positive semidefinite (clamping negative
  // eigenvalues to zero), otherwise it is exact.
  virtual void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                        HessianMode mode, MaterialEvaluation<Dim>& out) const = 0;

  // True when the tangent does not depend on F (linear elasticity): the energy is quadratic in
  // the positions, and Newton keeps one factorization per parameter vector.
  virtual bool tangent_is_constant() const { return false; }

  // Derivatives of Psi and P in (lambda, mu).
  virtual void lame_derivatives(const Mat& F, const LameParameters& lame,
                                MaterialLameDerivatives<Dim>& out) const = 0;

  // Optional closed form of a linear simplex's exact Hessian: a material that returns true from
  // has_simplex_hessian() writes V B^T T B (B = dvec(F)/dx over the element's node-major local
  // DOFs, T the exact tangent) into the (Dim+1)Dim x (Dim+1)Dim column-major array H, without
  // forming T. Rows of G are the rest shape gradients grad N_a.
  using NodeGradients = Eigen::Matrix<double, Dim + 1, Dim>;
  virtual bool has_simplex_hessian() const { return false; }
  virtual void simplex_hessian(const Mat& /*F*/, const LameParameters& /*lame*/, const NodeGradients& /*G*/,
                               double /*V*/, double* /*H*/) const {}
};

// A material by its registered name (forward/fem/material_registry.hpp). The constants name the
// built-in ones for C++ code; a material added later needs none (MaterialKind("my_material")).
// The kind does not own its name: give a string literal, or a run-time name through
// parse_material_kind, which checks it and views the registry's copy.
class MaterialKind {
 public:
  constexpr MaterialKind() = default;  // linear
  constexpr explicit MaterialKind(std::string_view name) : name_(name) {}
  constexpr std::string_view name() const { return name_; }
  friend constexpr bool operator==(MaterialKind a, MaterialKind b) { return a.name_ == b.name_; }

  static const MaterialKind linear;
  static const MaterialKind corotated;
  static const MaterialKind stvk;
  static const MaterialKind neo_hookean;

 private:
  std::string_view name_ = "linear";
};
inline constexpr MaterialKind MaterialKind::linear{"linear"};
inline constexpr MaterialKind MaterialKind::corotated{"corotated"};
inline constexpr MaterialKind MaterialKind::stvk{"stvk"};
inline constexpr MaterialKind MaterialKind::neo_hookean{"neo_hookean"};

// The registered material's Material<Dim>; std::invalid_argument naming the registered ones when
// the name is not registered.
template <int Dim>
std::unique_ptr<Material<Dim>> make_material(MaterialKind kind);
MaterialKind parse_material_kind(const std::string& name);  // throws std::invalid_argument naming the choices
std::string to_string(MaterialKind kind);
std::vector<std::string> material_names();  // registered_materials() order
std::ostream& operator<<(std::ostream& out, MaterialKind kind);

}  // namespace tailor
