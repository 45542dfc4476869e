#include "problems/fem/inverse_scene.hpp"

#include <sstream>
#include <stdexcept>
#include <utility>

#include "forward/core/format_number.hpp"
#include "optimizers/backend_registry.hpp"
#include "problems/fem/objective_term_registry.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/optimizer_section.hpp"

namespace tailor {

std::string to_string(DesignGranularity granularity) {
  switch (granularity) {
    case DesignGranularity::per_element:
      return "per_element";
    case DesignGranularity::per_region:
      return "per_region";
    case DesignGranularity::per_material:
      return "per_material";
    case DesignGranularity::modes:
      return "modes";
  }
  return "unknown";
}

std::string to_string(DesignMap map) { return map == DesignMap::log ? "log" : "identity"; }

namespace {

// {"value": E0, "gradient": [g...], "inclusions": [{"center": [...], "radius": r, "factor": f}]}:
// E = E0 (1 + g . c) * f (inside each sphere) at element centroids c. Dimensions and positivity
// are checked against the mesh when the field is expanded.
void parse_modulus_expression(const SceneNode& node, ModulusField& field) {
  node.expect_keys({"value", "gradient", "inclusions"});
  field.value = node.at("value").positive();
  if (auto g = node.find("gradient")) field.gradient = g->vector();
  if (auto list = node.find("inclusions"))
    for (const SceneNode& item : list->items()) {
      item.expect_keys({"center", "radius", "factor"});
      field.inclusions.push_back(
          {item.at("center").vector(), item.at("radius").positive(), item.at("factor").positive()});
    }
}

}  // namespace

// A number > 0, {"materials": [...]} with one value > 0 per materials[] entry, or
// {"file": path} with one value > 0 per mesh element.
ModulusField parse_modulus_field(const SceneNode& node, const std::string& directory) {
  ModulusField field;
  field.key = node.path();
  if (node.json().is_number()) {
    field.value = node.positive();
    return field;
  }
  if (!node.json().is_object())
    node.fail(
        "expected a number > 0, {\"materials\": [one value per material]}, {\"file\": path} (one "
        "value per element) or {\"value\": E0, \"gradient\": [...], \"inclusions\": [...]}, got " +
        describe_json(node.json()));
  if (node.find("value")) {
    parse_modulus_expression(node, field);
  } else if (node.only_key({"materials", "file", "value"}) == "file") {
    field.values = read_positive_values(node.at("file"), directory);
  } else {
    for (const SceneNode& item : node.at("materials").items()) field.per_material.push_back(item.positive());
    if (field.per_material.empty())
      node.at("materials").fail("expected one value per materials[] entry, got none");
  }
  return field;
}

namespace {

// "modes": r (integer >= 1) or "full"; "mode_weighting"; "output_modes": k in [0, r]. Only
// with granularity "modes". Bounds must come in pairs there: the smooth box of
// inverse_modes.hpp needs both ends (the log map alone already keeps E > 0).
void parse_mode_keys(const SceneNode& node, DesignSpec& d) {
  const bool modal = d.granularity == DesignGranularity::modes;
  for (const char* key : {"modes", "mode_weighting", "output_modes", "reduction"})
    if (auto k = node.find(key); k && !modal)
      k->fail("only with \"granularity\": \"modes\" (the granularity is " + to_string(d.granularity) + ")");
  if (!modal) return;
  const SceneNode modes = node.at("modes");
  if (modes.json().is_string()) {
    if (modes.choice({"full"}) == "full") d.modes.reset();
  } else {
    if (!modes.json().is_number_integer())
      modes.fail("expected an integer >= 1 or \"full\", got " + describe_json(modes.json()));
    d.modes = modes.integer(1);
  }
  if (auto w = node.find("mode_weighting"))
    d.mode_weighting = w->choice({"unit", "facet"}) == "unit" ? AdjacencyWeighting::unit
                                                              : AdjacencyWeighting::facet_over_distance;
  if (auto k = node.find("output_modes")) {
    d.output_modes = k->integer(0);
    if (d.modes && d.output_modes > *d.modes)
      k->fail("at most the number of modes (" + std::to_string(*d.modes) + "), got " +
              std::to_string(d.output_modes));
  }
  if (static_cast<bool>(d.min) != static_cast<bool>(d.max))
    node.at(d.min ? "min" : "max")
        .fail(
            "with granularity \"modes\" give both min and max (a smooth box keeps E inside them) or neither");
  if (d.reduction) {
    if (!d.modes)
      node.at("modes").fail("the reduced design loop needs a number of material modes, not \"full\"");
    if (d.map != DesignMap::identity || !node.has("map"))
      node.at("reduction")
          .fail(
              "give \"map\": \"identity\": the reduced loop designs E = E0 (1 + sum_j w_j y_j), "
              "linear in the mode coordinates w, which makes its precomputed reduced forces exact "
              "(the log map and the smooth box are not linear)");
    if (d.min || d.max)
      node.at(d.min ? "min" : "max")
          .fail("not with \"reduction\": E = E0 (1 + sum_j w_j y_j) is linear in w and has no box");
    return;
  }
  if (d.map == DesignMap::identity && !d.min)
    node.fail(
        "granularity \"modes\" with the identity map needs min and max (E = Phi z alone may turn negative); "
        "or use the log map");
}

ReductionSpec parse_reduction(const SceneNode& node) {
  node.expect_keys({"displacement_modes", "modal_derivatives", "derivative_modes", "static_responses",
                    "design_responses", "smoothness", "full_space_check", "min_relative_modulus",
                    "positivity_weight", "refinements", "full_space_tolerance", "cubature", "krylov_order",
                    "basis", "domains"});
  ReductionSpec r;
  r.key = node.path();
  if (auto k = node.find("displacement_modes")) r.displacement_modes = k->integer(1);
  if (auto k = node.find("modal_derivatives")) r.modal_derivatives = k->boolean();
  if (auto k = node.find("derivative_modes")) r.derivative_modes = k->integer(0);
  if (auto k = node.find("static_responses")) r.static_responses = k->boolean();
  if (auto k = node.find("design_responses")) r.design_responses = k->boolean();
  if (auto k = node.find("smoothness")) r.smoothness = k->non_negative();
  if (auto k = node.find("full_space_check")) r.full_space_check = k->boolean();
  if (auto k = node.find("refinements")) r.refinements = k->integer(0);
  if (auto k = node.find("full_space_tolerance")) r.full_space_tolerance = k->positive();
  if (auto k = node.find("min_relative_modulus")) r.min_relative_modulus = k->open_interval(0.0, 1.0);
  if (auto k = node.find("positivity_weight")) r.positivity_weight = k->non_negative();
  if (auto k = node.find("krylov_order")) r.krylov_order = k->integer(1);
  if (r.krylov_order > 4) node.at("krylov_order").fail("at most 4 (the block sizes grow as C(r + k - 1, k))");
  if (auto k = node.find("basis")) r.basis = k->choice({"global", "domains", "overlapping"});
  if (auto k = node.find("domains")) {
    if (r.basis == "global") k->fail("only with \"basis\": \"domains\" or \"overlapping\"");
    k->expect_keys({"count", "from_regions", "fixed_interface_modes", "derivative_modes", "interface_modes",
                    "overlap_layers"});
    auto& d = r.domains;
    if (auto e = k->find("count")) d.count = e->integer(1);
    if (auto e = k->find("from_regions")) d.from_regions = e->boolean();
    if (auto e = k->find("fixed_interface_modes")) d.fixed_interface_modes = e->integer(0);
    if (auto e = k->find("derivative_modes")) d.derivative_modes = e->integer(0);
    if (auto e = k->find("interface_modes")) d.interface_modes = e->integer(0);
    if (auto e = k->find("overlap_layers")) d.overlap_layers = e->integer(0);
  }
  if (auto k = node.find("cubature")) {
    k->expect_keys({"elements", "training_poses", "tolerance", "candidates"});
    CubatureSpec c;
    if (auto e = k->find("elements")) c.elements = e->integer(1);
    if (auto e = k->find("training_poses")) c.training_poses = e->integer(1);
    if (auto e = k->find("tolerance")) c.tolerance = e->positive();
    if (auto e = k->find("candidates")) c.candidates = e->integer(0);
    r.cubature = c;
  }
  return r;
}

DesignSpec parse_design(const SceneNode& node) {
  node.expect_keys({"parameter", "granularity", "map", "min", "max", "initial", "modes", "mode_weighting",
                    "output_modes", "reduction"});
  DesignSpec d;
  if (auto k = node.find("reduction")) d.reduction = parse_reduction(*k);
  const SceneNode parameter = node.at("parameter");
  d.parameter = parameter.string();
  if (d.parameter != "youngs_modulus")
    parameter.fail("only \"youngs_modulus\" can be designed (for now), got \"" + d.parameter + "\"");
  const std::string granularity =
      node.at("granularity").choice({"per_element", "per_region", "per_material", "modes"});
  d.granularity = granularity == "per_element"    ? DesignGranularity::per_element
                  : granularity == "per_region"   ? DesignGranularity::per_region
                  : granularity == "per_material" ? DesignGranularity::per_material
                                                  : DesignGranularity::modes;
  if (auto m = node.find("map"))
    d.map = m->choice({"log", "identity"}) == "log" ? DesignMap::log : DesignMap::identity;

  // Bounds on E become bounds on z: their logarithms for the log map, which therefore needs
  // them > 0. Moduli are never negative, whatever the map.
  const auto bound = [&](const char* key) -> std::optional<double> {
    auto b = node.find(key);
    if (!b) return std::nullopt;
    const double v = b->number();
    if (d.map == DesignMap::log && !(v > 0.0))
      b->fail("with the log map (z = log E) the bound must be > 0, got " + format_number(v));
    if (v < 0.0) b->fail("expected a number >= 0 (Young's modulus), got " + format_number(v));
    return v;
  };
  d.min = bound("min");
  d.max = bound("max");
  if (d.min && d.max && !(*d.max > *d.min))
    node.at("max").fail("must be > min (" + format_number(*d.min) + "), got " + format_number(*d.max));
  parse_mode_keys(node, d);
  if (auto i = node.find("initial")) {
    d.initial = i->positive();
    if ((d.min && *d.initial < *d.min) || (d.max && *d.initial > *d.max))
      i->fail("lies outside the bounds [" + (d.min ? format_number(*d.min) : "-inf") + ", " +
              (d.max ? format_number(*d.max) : "inf") + "]");
  }
  return d;
}

// The term's type from the registry; its keys checked, then parsed by the type's parse.
ObjectiveTermSpec parse_term(const SceneNode& node, const std::string& directory) {
  ObjectiveTermSpec spec;
  spec.key = node.path();
  spec.kind = find_objective_term_type(node.at("type").choice(objective_term_types()));
  std::vector<std::string> keys = {"type", "weight"};
  keys.insert(keys.end(), spec.kind->keys.begin(), spec.kind->keys.end());
  node.expect_keys(keys);
  for (const std::string& key : spec.kind->required) node.at(key.c_str());
  if (spec.kind->parse) spec.settings = spec.kind->parse(node, directory);
  spec.value = node.json();
  if (auto w = node.find("weight")) spec.weight = w->non_negative();
  return spec;
}

// The data term types, for the message of a list without one.
std::string data_term_types() {
  std::string out;
  for (const std::string& type : objective_term_types())
    if (find_objective_term_type(type)->is_data) out += (out.empty() ? "" : ", ") + type;
  return out;
}

OptimizerOptions parse_optimizer(const SceneNode& node) {
  return parse_optimizer_section(node, OptimizerOptions{}, {"an inverse FEM scene", true, true, {}});
}

TaylorTestOptions parse_gradcheck(const SceneNode& node) {
  node.expect_keys({"seed", "initial_step", "halvings"});
  TaylorTestOptions t;
  if (auto v = node.find("seed")) t.seed = static_cast<unsigned>(v->integer(0));
  if (auto v = node.find("initial_step")) t.initial_step = v->positive();
  if (auto v = node.find("halvings")) t.halvings = v->integer(4);
  return t;
}

}  // namespace

InverseSpec parse_inverse_section(const SceneNode& node, const std::string& directory) {
  return parse_inverse_section(node, directory, false);
}

InverseSpec parse_inverse_section(const SceneNode& node, const std::string& directory,
                                  bool other_data_terms) {
  node.expect_keys({"design", "objective", "ground_truth", "optimizer", "gradcheck"});
  InverseSpec spec;
  spec.design = parse_design(node.at("design"));
  const SceneNode objective = node.at("objective");
  bool has_data = false;
  for (const SceneNode& item : objective.items()) {
    spec.objective.push_back(parse_term(item, directory));
    has_data = has_data || spec.objective.back().is_data();
  }
  if (!has_data && !other_data_terms)
    objective.fail("needs at least one data term (" + data_term_types() +
                   "); regularization alone has nothing to fit");
  // log E needs E > 0, which only the log map or a positive lower bound guarantees.
  const bool positive = spec.design.map == DesignMap::log || (spec.design.min && *spec.design.min > 0.0);
  for (std::size_t k = 0; k < spec.objective.size(); ++k) {
    const auto* smoothness = spec.objective[k].settings_as<SmoothnessTerm>();
    if (smoothness && smoothness->logarithmic && !positive)
      objective.items()[k].fail(
          "smoothness on log E needs E > 0: with the identity map give inverse.design.min > 0, use \"on\": "
          "\"value\", or the log map");
  }
  int handle_terms = 0;
  for (std::size_t k = 0; k < spec.objective.size(); ++k)
    if (spec.objective[k].settings_as<HandlesTerm>() && ++handle_terms > 1)
      objective.items()[k].fail("at most one \"handles\" term; list every handle in the first one");
  if (auto truth = node.find("ground_truth")) {
    truth->expect_keys({"youngs_modulus"});
    spec.ground_truth = parse_modulus_field(truth->at("youngs_modulus"), directory);
  }
  if (auto o = node.find("optimizer")) spec.optimizer = parse_optimizer(*o);
  // Modal designs keep E inside the bounds by a smooth box, not by optimizer bounds.
  const bool bounded =
      (spec.design.min || spec.design.max) && spec.design.granularity != DesignGranularity::modes;
  if (bounded && !find_backend(spec.optimizer.backend).capabilities.bounds)
    node.at("optimizer")
        .at("backend")
        .fail(to_string(spec.optimizer.backend) +
              " does not support bounds, but inverse.design has min/max (remove them or choose one of " +
              backends_with(&BackendCapabilities::bounds) + ")");
  if (auto g = node.find("gradcheck")) spec.gradcheck = parse_gradcheck(*g);
  return spec;
}

}  // namespace tailor
