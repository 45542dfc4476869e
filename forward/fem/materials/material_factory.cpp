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

std::vector<std::string> material_names() {
  std::vector<std::string> names;
  for (const MaterialName& entry : kMaterialNames) names.emplace_back(entry.name);
  return names;
}

MaterialKind parse_material_kind(const std::string& name) {
  for (const MaterialName& entry : kMaterialNames)
    if (name == entry.name) return entry.kind;
  std::string list;
  for (const MaterialName& entry : kMaterialNames) list += (list.empty() ? "" : ", ") + std::string(entry.name);
  throw std::invalid_argument("unknown material '" + name + "' (expected one of " + list + ")");
}

std::string to_string(MaterialKind kind) {
  for (const MaterialName& entry : kMaterialNames)
    if (entry.kind == kind) return entry.name;
  throw std::invalid_argument("to_string: invalid MaterialKind value " + std::to_string(static_cast<int>(kind)));
}

}  // namespace tailor
