#include "problems/material_fit/material_fit_scene.hpp"

#include "optimizers/backend_registry.hpp"
#include "problems/fem/scene.hpp"
#include "problems/optimizer_section.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

SplineGrid parse_grid(const SceneNode& node) {
  node.expect_keys({"lower", "upper", "intervals"});
  SplineGrid g{node.at("lower").number(), node.at("upper").number(), node.at("intervals").integer(1)};
  if (!(g.lower < g.upper)) node.fail("expected lower < upper");
  return g;
}

// {"material" | "preset": name, "youngs_modulus": E, "poisson_ratio": nu}
LameParameters parse_moduli(const SceneNode& node) {
  const double E = node.at("youngs_modulus").positive();
  const double nu = node.at("poisson_ratio").open_interval(-1.0, 0.5);
  return lame_from_young_poisson(E, nu);
}

SplinePreset parse_preset(const SceneNode& node) {
  return parse_spline_preset(node.choice({"corotated", "stvk", "neo_hookean"}));
}

// {"curve": name, "kind": "increasing" | "decreasing" | "convex" | "concave", "range": [lo, hi]}
// (range optional: the whole curve).
ShapeConstraint parse_shape_constraint(const SceneNode& node) {
  node.expect_keys({"curve", "kind", "range"});
  ShapeConstraint s;
  s.curve = node.at("curve").choice({"uniaxial", "biaxial", "volumetric"});
  s.shape = parse_curve_shape(node.at("kind").choice({"increasing", "decreasing", "convex", "concave"}));
  if (auto range = node.find("range")) {
    const Eigen::VectorXd r = range->vector(2);
    if (!(r[0] < r[1])) range->fail("expected [lower, upper] with lower < upper");
    s.lower = r[0];
    s.upper = r[1];
  }
  return s;
}

}  // namespace

MaterialFitSpec parse_material_fit_scene(const SceneNode& root) {
  root.expect_keys({"name", "type", "description", "specimen", "curves", "load_cases", "reference", "initial",
                    "smoothness", "convex", "shape", "optimizer"});
  if (root.at("type").string() != "material_fit") root.at("type").fail("expected \"material_fit\"");
  MaterialFitSpec spec;
  spec.source = root.source();
  if (auto n = root.find("name")) spec.name = n->string();
  if (auto d = root.find("description")) d->string();
  if (auto s = root.find("specimen")) {
    s->expect_keys({"cells"});
    spec.cells = s->at("cells").integer(2);
  }
  const SceneNode curves = root.at("curves");
  curves.expect_keys({"uniaxial", "biaxial", "volumetric"});
  spec.grids.uniaxial = parse_grid(curves.at("uniaxial"));
  spec.grids.biaxial = parse_grid(curves.at("biaxial"));
  spec.grids.volumetric = parse_grid(curves.at("volumetric"));

  const SceneNode cases = root.at("load_cases");
  for (const SceneNode& item : cases.items()) {
    item.expect_keys({"name", "kind", "amplitudes", "forces"});
    LoadCase c;
    c.name = item.at("name").string();
    c.kind = parse_load_case_kind(item.at("kind").choice({"uniaxial", "biaxial", "shear"}));
    const SceneNode amplitudes = item.at("amplitudes");
    if (!amplitudes.json().is_array() || amplitudes.json().empty())
      amplitudes.fail("expected a non-empty array of numbers");
    const Eigen::VectorXd a = amplitudes.vector(static_cast<int>(amplitudes.json().size()));
    c.amplitudes.assign(a.data(), a.data() + a.size());
    for (double v : c.amplitudes)
      if (c.kind != LoadCaseKind::shear && !(v > 0.0)) amplitudes.fail("stretches must be > 0");
    if (auto f = item.find("forces")) {
      if (!f->json().is_array() || f->json().size() != c.amplitudes.size())
        f->fail("expected one force per amplitude (" + std::to_string(c.amplitudes.size()) + ")");
      const Eigen::VectorXd v = f->vector(static_cast<int>(c.amplitudes.size()));
      spec.target_forces.emplace_back(v.data(), v.data() + v.size());
    }
    spec.cases.push_back(c);
  }
  if (spec.cases.empty()) cases.fail("expected at least one load case");

  if (auto r = root.find("reference")) {
    if (!spec.target_forces.empty())
      r->fail("give either a reference or target forces in the load cases, not both");
    r->expect_keys({"material", "preset", "youngs_modulus", "poisson_ratio"});
    if (r->has("material") == r->has("preset"))
      r->fail("expected exactly one of \"material\" and \"preset\"");
    if (r->has("material"))
      spec.reference_material = parse_material_kind(r->at("material").choice(material_names()));
    else
      spec.reference_preset = parse_preset(r->at("preset"));
    spec.reference_lame = parse_moduli(*r);
  } else if (spec.target_forces.size() != spec.cases.size()) {
    cases.fail("without a \"reference\", every load case needs \"forces\"");
  }

  const SceneNode initial = root.at("initial");
  initial.expect_keys({"preset", "youngs_modulus", "poisson_ratio"});
  spec.initial_preset = parse_preset(initial.at("preset"));
  spec.initial_lame = parse_moduli(initial);

  if (auto s = root.find("smoothness")) spec.smoothness = s->non_negative();
  if (auto c = root.find("convex"))
    for (const SceneNode& item : c->items())
      spec.shapes.push_back({item.choice({"uniaxial", "biaxial", "volumetric"}), CurveShape::convex});
  if (auto list = root.find("shape"))
    for (const SceneNode& item : list->items()) spec.shapes.push_back(parse_shape_constraint(item));
  spec.optimizer.backend = OptimizerBackend::ceres_least_squares;
  if (auto o = root.find("optimizer"))
    spec.optimizer = parse_optimizer_section(*o, spec.optimizer, {"a material fit", false, false, {}});
  if (!spec.shapes.empty() && !find_backend(spec.optimizer.backend).capabilities.inequality_constraints)
    root.at(root.has("convex") ? "convex" : "shape")
        .fail("shape constraints need a constrained optimizer (" +
              backends_with(&BackendCapabilities::inequality_constraints) + ")");
  return spec;
}

}  // namespace tailor
