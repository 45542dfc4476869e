#pragma once
// The registry of hyperelastic materials: every name a scene, a test or a program can give a
// material, with its 2D and 3D factories and what the layers above may assume about it.
//
// Adding a built-in material is one file under forward/fem/materials/ (and its test): the class,
// and at namespace tailor scope a function
//     MaterialEntry <name>_material_entry() { return make_material_entry<MyMaterial>(...); }
// The build lists every such function in that folder (cmake/tailorWriteRegistryList.cmake), and
// the registry adds them before its first use, in file-name order. Scenes then accept the name,
// and the material tests (tests/forward/fem_materials) check it with every other registered one.
// A program adds its own with register_material before it reads a scene.
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "forward/fem/material.hpp"

namespace tailor {

// What code above forward/ may assume about a material without naming it.
struct MaterialTraits {
  // Psi is a polynomial in the entries of F (linear elasticity: quadratic, StVK: quartic), so
  // reduced internal forces are exact polynomials in the reduced coordinates
  // (problems/fem/reduced_design.cpp builds the polynomial model only for these).
  bool polynomial_in_deformation = false;
};

struct MaterialEntry {
  std::string name;     // as scenes write it: lowercase letters, digits and '_'
  std::string summary;  // one line
  MaterialTraits traits;
  std::function<std::unique_ptr<Material<2>>()> make_2d;
  std::function<std::unique_ptr<Material<3>>()> make_3d;
};

// The entry of a material class template M<Dim> that is default-constructible for Dim = 2, 3.
template <template <int> class M>
MaterialEntry make_material_entry(std::string name, std::string summary, MaterialTraits traits = {}) {
  return {std::move(name), std::move(summary), traits,
          [] { return std::unique_ptr<Material<2>>(new M<2>()); },
          [] { return std::unique_ptr<Material<3>>(new M<3>()); }};
}

// Adds a material. std::invalid_argument when the name is empty, not of [a-z0-9_], or taken, or
// when a factory is missing.
void register_material(MaterialEntry entry);
// The entry of a registered material; std::invalid_argument naming the registered ones otherwise.
const MaterialEntry& find_material(MaterialKind kind);
// Every registered material: the built-in ones in file-name order, then the program's own.
std::vector<const MaterialEntry*> registered_materials();

}  // namespace tailor
