// The material registry (forward/fem/material_registry.hpp): the built-in materials register
// themselves from their own files, a program's material is registered the same way, bad entries
// are refused, and each entry's traits tell the truth about its energy.
#include "forward/fem/material_registry.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "forward/fem/materials/linear.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::material_registry_test {
namespace {

TEST(MaterialRegistry, BuiltInMaterialsRegisterThemselves) {
  std::vector<std::string> names;
  for (const MaterialEntry* entry : registered_materials()) names.push_back(entry->name);
  // The four of forward/fem/materials/, in file-name order, before any program's own.
  ASSERT_GE(names.size(), 4u);
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 4),
            (std::vector<std::string>{"corotated", "linear", "neo_hookean", "stvk"}));
  EXPECT_EQ(material_names(), names);
  for (const MaterialEntry* entry : registered_materials()) {
    EXPECT_FALSE(entry->summary.empty()) << entry->name;
    EXPECT_EQ(&find_material(parse_material_kind(entry->name)), entry);
  }
  EXPECT_EQ(parse_material_kind("stvk"), MaterialKind::stvk);
  EXPECT_EQ(MaterialKind(), MaterialKind::linear);
}

TEST(MaterialRegistry, UnknownNamesNameTheRegisteredOnes) {
  try {
    make_material<3>(MaterialKind("neohookean"));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(),
                ::testing::HasSubstr("unknown material 'neohookean' (expected one of corotated, linear"));
  }
  EXPECT_THROW(parse_material_kind("Linear"), std::invalid_argument);
}

// Twice the linear material: a complete material defined outside forward/, as a program would.
template <int Dim>
class DoubledLinear final : public Material<Dim> {
 public:
  using typename Material<Dim>::Mat;
  std::string name() const override { return "test_doubled_linear"; }
  bool tangent_is_constant() const override { return true; }
  void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                HessianMode mode, MaterialEvaluation<Dim>& out) const override {
    base_.evaluate(F, lame, want_stress, want_tangent, mode, out);
    out.energy_density *= 2.0;
    if (want_stress) out.stress *= 2.0;
    if (want_tangent) out.tangent *= 2.0;
  }
  void lame_derivatives(const Mat& F, const LameParameters& lame,
                        MaterialLameDerivatives<Dim>& out) const override {
    base_.lame_derivatives(F, lame, out);
    out.energy_density *= 2.0;
    out.stress *= 2.0;
  }

 private:
  LinearMaterial<Dim> base_;
};

TEST(MaterialRegistry, AProgramRegistersItsOwnMaterial) {
  register_material(make_material_entry<DoubledLinear>("test_doubled_linear", "twice linear elasticity",
                                                       {.polynomial_in_deformation = true}));
  const MaterialKind kind = parse_material_kind("test_doubled_linear");
  EXPECT_EQ(make_material<2>(kind)->name(), "test_doubled_linear");
  const std::vector<std::string> names = material_names();
  EXPECT_EQ(names.back(), "test_doubled_linear");
  Mat<3> F;
  F << 1.1, 0.2, 0.0, -0.1, 0.9, 0.3, 0.05, 0.0, 1.2;
  const LameParameters lame = lame_from_young_poisson(2.0, 0.3);
  MaterialEvaluation<3> a, b;
  make_material<3>(kind)->evaluate(F, lame, false, false, HessianMode::exact, a);
  make_material<3>(MaterialKind::linear)->evaluate(F, lame, false, false, HessianMode::exact, b);
  EXPECT_DOUBLE_EQ(a.energy_density, 2.0 * b.energy_density);
  // A name can be registered once; bad names and missing factories are refused.
  EXPECT_THROW(register_material(make_material_entry<DoubledLinear>("test_doubled_linear", "again")),
               std::invalid_argument);
  EXPECT_THROW(register_material(make_material_entry<DoubledLinear>("linear", "a built-in name")),
               std::invalid_argument);
  EXPECT_THROW(register_material(make_material_entry<DoubledLinear>("", "empty")), std::invalid_argument);
  EXPECT_THROW(register_material(make_material_entry<DoubledLinear>("Doubled Linear", "spaces")),
               std::invalid_argument);
  MaterialEntry no_3d = make_material_entry<DoubledLinear>("test_no_3d", "2D only");
  no_3d.make_3d = nullptr;
  EXPECT_THROW(register_material(no_3d), std::invalid_argument);
  EXPECT_EQ(material_names(), names);
}

// The fifth difference of t -> Psi(F0 + t D) vanishes for a polynomial of degree <= 4 in F and
// not otherwise, so the trait "polynomial_in_deformation" is checked against the energy itself.
template <int Dim>
double fifth_difference(const Material<Dim>& material, const Mat<Dim>& F0, const Mat<Dim>& D, double h) {
  const LameParameters lame = lame_from_young_poisson(3.7, 0.3);
  const double binomial[6] = {1, -5, 10, -10, 5, -1};
  double sum = 0.0;
  for (int k = 0; k <= 5; ++k) {
    MaterialEvaluation<Dim> e;
    material.evaluate(F0 + (k - 2.5) * h * D, lame, false, false, HessianMode::exact, e);
    sum += binomial[k] * e.energy_density;
  }
  return std::abs(sum) / std::pow(h, 5);
}

TEST(MaterialRegistry, PolynomialTraitMatchesTheEnergy) {
  Mat<3> F0, D;
  F0 << 1.1, 0.2, 0.0, -0.1, 0.9, 0.3, 0.05, 0.0, 1.2;
  D << 0.3, -0.2, 0.1, 0.0, 0.4, -0.3, 0.2, 0.1, -0.1;
  int polynomial = 0, not_polynomial = 0;
  for (const MaterialEntry* entry : registered_materials()) {
    SCOPED_TRACE(entry->name);
    const double d5 = fifth_difference<3>(*entry->make_3d(), F0, D, 0.1);
    // Round-off of the sum is ~1e-15 * Psi / h^5 = 1e-10; a non-polynomial energy gives O(1).
    if (entry->traits.polynomial_in_deformation) {
      EXPECT_LT(d5, 1e-6);
      ++polynomial;
    } else {
      EXPECT_GT(d5, 1e-3);
      ++not_polynomial;
    }
  }
  EXPECT_GE(polynomial, 2);      // linear, StVK
  EXPECT_GE(not_polynomial, 2);  // corotated, Neo-Hookean: the check can fail
}

}  // namespace
}  // namespace tailor::test::material_registry_test
