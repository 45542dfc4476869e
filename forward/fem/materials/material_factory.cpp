// make_material / parse_material_kind / to_string (declared in forward/fem/material.hpp).
#include <memory>
#include <stdexcept>
#include <string>

#include "forward/fem/material.hpp"
#include "forward/fem/materials/corotated.hpp"
#include "forward/fem/materials/linear.hpp"
#include "forward/fem/materials/neo_hookean.hpp"
#include "forward/fem/materials/stvk.hpp"

namespace tailor {

template <int Dim>
std::unique_ptr<Material<Dim>> make_material(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::linear:
      return std::make_unique<LinearMaterial<Dim>>();
    case MaterialKind::corotated:
      return std::make_unique<CorotatedMaterial<Dim>>();
    case MaterialKind::stvk:
      return std::make_unique<StvkMaterial<Dim>>();
    case MaterialKind::neo_hookean:
      return std::make_unique<NeoHookeanMaterial<Dim>>();
  }
  throw std::invalid_argument("make_material: invalid MaterialKind value " +
                              std::to_string(static_cast<int>(kind)));
}

template std::unique_ptr<Material<2>> make_material<2>(MaterialKind);
template std::unique_ptr<Material<3>> make_material<3>(MaterialKind);

MaterialKind parse_material_kind(const std::string& name) {
  for (MaterialKind kind :
       {MaterialKind::linear, MaterialKind::corotated, MaterialKind::stvk, MaterialKind::neo_hookean})
    if (name == to_string(kind)) return kind;
  throw std::invalid_argument("unknown material '" + name +
                              "' (expected linear, corotated, stvk or neo_hookean)");
}

std::string to_string(MaterialKind kind) {
  switch (kind) {
    case MaterialKind::linear:
      return "linear";
    case MaterialKind::corotated:
      return "corotated";
    case MaterialKind::stvk:
      return "stvk";
    case MaterialKind::neo_hookean:
      return "neo_hookean";
  }
  throw std::invalid_argument("to_string: invalid MaterialKind value " +
                              std::to_string(static_cast<int>(kind)));
}

}  // namespace tailor
