#include "problems/fem/spline_curves_json.hpp"

#include <cstdint>
#include <fstream>
#include <sstream>

#include "forward/fem/materials/spline_material.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "tailor_version.hpp"

namespace tailor {
namespace {

CubicSpline parse_curve(const SceneNode& node) {
  node.expect_keys({"lower", "upper", "intervals", "controls"});
  const double lower = node.at("lower").number();
  const double upper = node.at("upper").number();
  if (!(lower < upper)) node.at("upper").fail("expected a number > lower (" + std::to_string(lower) + ")");
  const int intervals = node.at("intervals").integer(1);
  const SceneNode controls = node.at("controls");
  // In 64 bits: intervals may be up to INT_MAX - 1.
  const std::int64_t expected = std::int64_t{intervals} + 3;
  if (!controls.json().is_array() || static_cast<std::int64_t>(controls.json().size()) != expected)
    controls.fail("expected intervals + 3 = " + std::to_string(expected) + " control values, got " +
                  describe_json(controls.json()));
  return CubicSpline(lower, upper, intervals, controls.vector(static_cast<int>(expected)));
}

nlohmann::json curve_json(const CubicSpline& c) {
  const Eigen::VectorXd& v = c.controls();
  return nlohmann::json{{"lower", c.lower()},
                        {"upper", c.upper()},
                        {"intervals", c.intervals()},
                        {"controls", std::vector<double>(v.data(), v.data() + v.size())}};
}

}  // namespace

PrincipalStretchCurves parse_principal_stretch_curves(const SceneNode& node) {
  node.expect_keys({"uniaxial", "biaxial", "volumetric"});
  return {parse_curve(node.at("uniaxial")), parse_curve(node.at("biaxial")),
          parse_curve(node.at("volumetric"))};
}

PrincipalStretchCurves parse_curves_or_file(const SceneNode& node, const std::string& directory) {
  if (!node.has("file")) return parse_principal_stretch_curves(node);
  node.expect_keys({"file"});
  const SceneNode file = node.at("file");
  const std::string path = resolve_scene_path(directory, file.string());
  std::ifstream in(path);
  if (!in) file.fail("cannot open file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  const nlohmann::json document = parse_json_or_discarded(text.str());
  if (document.is_discarded()) file.fail("'" + path + "' is not valid JSON");
  try {
    const SceneNode root(document, path, "");
    if (!document.is_object() || !root.has("curves"))
      root.fail("expected an object with a \"curves\" member (a material-fit run's material.json)");
    return parse_principal_stretch_curves(root.at("curves"));
  } catch (const SceneError& e) {
    file.fail(e.what());
  }
}

nlohmann::json principal_stretch_curves_json(const PrincipalStretchCurves& curves) {
  return {{"uniaxial", curve_json(curves.uniaxial)},
          {"biaxial", curve_json(curves.biaxial)},
          {"volumetric", curve_json(curves.volumetric)}};
}

void write_spline_material_file(const std::string& path, const PrincipalStretchCurves& curves,
                                const std::string& source) {
  const nlohmann::ordered_json file = {{"tailor_version", version_string},
                                       {"source", source},
                                       {"curves", principal_stretch_curves_json(curves)}};
  write_text_file_atomically(path, dump_json(file, 2) + "\n");
}

LameParameters small_strain_lame(const PrincipalStretchCurves& curves) {
  // At F = I the tangent is the linear elasticity tensor: C_0000 = lambda + 2 mu, C_0011 = lambda
  // (column-major vec: entry (1, 1) is index 4).
  MaterialEvaluation<3> rest;
  evaluate_spline_material<3>(curves, Eigen::Matrix3d::Identity(), false, true, HessianMode::exact, rest);
  const double lambda = rest.tangent(0, 4);
  return {lambda, 0.5 * (rest.tangent(0, 0) - lambda)};
}

}  // namespace tailor
