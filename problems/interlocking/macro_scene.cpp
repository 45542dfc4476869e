// The "interlocking_macro" scene: fit a measured boundary, drape the macro-scale sheet over a
// sphere (see macro_scene.hpp).
#include "problems/interlocking/macro_scene.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include "problems/contact/surface_vtu.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/report_file.hpp"

namespace tailor {
namespace {

using nlohmann::ordered_json;

// A UV sphere of `radius` about the origin for the VTU (rings x segments quads split in two).
void sphere_surface(double radius, int rings, int segments, Eigen::MatrixX3d& v, Eigen::MatrixX3i& f) {
  v.resize((rings + 1) * segments, 3);
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = M_PI * i / rings, phi = 2.0 * M_PI * j / segments;
      v.row(i * segments + j) << radius * std::sin(theta) * std::cos(phi),
          radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta);
    }
  f.resize(2 * rings * segments, 3);
  int k = 0;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments, c = a + segments,
                d = b + segments;
      f.row(k++) << a, c, b;
      f.row(k++) << b, c, d;
    }
}

// The principal section (e_xy = 0) of the fitted set in the (e_xx, e_yy) plane, with the native
// samples on it.
void write_fit_plot(const std::string& path, const std::string& title, const InterlockingMacroScene& scene,
                    const interlocking::MacroStrainSet& set) {
  LineSeries samples{"native limits (e_xy = 0)", {200, 30, 30}, {}, {}}, fitted{"fit", {30, 60, 200}, {}, {}};
  for (const Eigen::Vector2d& e : scene.limit_strains) {
    samples.x.push_back(e.x());
    samples.y.push_back(e.y());
  }
  for (const Eigen::Vector3d& e : scene.oriented_strains)
    if (std::abs(e.z()) < 1e-9) {
      samples.x.push_back(e.x());
      samples.y.push_back(e.y());
    }
  for (int k = 0; k <= 360; ++k) {
    const double t = 2.0 * M_PI * k / 360;
    const double r = set.radius_along(Eigen::Vector3d(std::cos(t), std::sin(t), 0.0));
    fitted.x.push_back(r * std::cos(t));
    fitted.y.push_back(r * std::sin(t));
  }
  LinePlot plot;
  plot.title = title;
  plot.x_label = "e_xx";
  plot.y_label = "e_yy";
  plot.width = plot.height = 640;
  plot.series = {fitted, samples};
  write_line_plot_png(path, plot);
}

ordered_json fit_report(const InterlockingMacroScene& scene, const interlocking::MacroStrainSet& set) {
  ordered_json coefficients = ordered_json::array();
  const double q = std::sqrt(0.5);
  ordered_json fit;
  if (set.anisotropic) {
    const interlocking::AnisotropicBoundaryFit& f = set.oriented;
    for (double c : f.coefficients) coefficients.push_back(c);
    fit = {{"set", "anisotropic"},
           {"degree", f.degree},
           {"max_order", f.max_order},
           {"symmetry", {{"reflect", scene.symmetry.reflect}, {"swap", scene.symmetry.swap}}},
           {"samples", f.samples},
           {"harmonic_coefficients", coefficients},
           {"rms_residual", f.rms_residual},
           {"max_residual", f.max_residual},
           {"min_radius", f.min_radius}};
  } else {
    const interlocking::BoundaryFit& f = set.isotropic;
    for (double c : f.coefficients) coefficients.push_back(c);
    fit = {{"set", "isotropic"},
           {"order", scene.order},
           {"samples", f.samples},
           {"chebyshev_coefficients", coefficients},
           {"rms_residual", f.rms_residual},
           {"max_residual", f.max_residual},
           {"min_radius", f.min_radius}};
  }
  ordered_json uniaxial = ordered_json::array();
  for (int degrees : {0, 45, 90, 135})
    uniaxial.push_back({{"angle_degrees", degrees},
                        {"limit", interlocking::macro_uniaxial_limit(set, degrees * M_PI / 180.0)}});
  fit["uniaxial_limits"] = uniaxial;
  fit["equibiaxial_stretch_limit"] = set.radius_along(Eigen::Vector3d(q, q, 0.0));  // rho = |e|
  fit["equibiaxial_compression_limit"] = set.radius_along(Eigen::Vector3d(-q, -q, 0.0));
  return fit;
}

}  // namespace

interlocking::MacroStrainSet macro_strain_set(const InterlockingMacroScene& scene) {
  if (scene.anisotropic)
    return interlocking::fit_anisotropic_boundary(scene.oriented_strains, scene.degree, scene.max_order,
                                                  scene.symmetry);
  return interlocking::fit_boundary(scene.limit_strains, scene.order);
}

InterlockingMacroScene parse_interlocking_macro_scene(const SceneNode& root) {
  root.expect_keys({"name", "description", "interlocking_macro"});
  const SceneNode n = root.at("interlocking_macro");
  n.expect_keys({"boundary", "bending_limits", "material", "drape"});
  InterlockingMacroScene scene;
  const SceneNode b = n.at("boundary");
  b.expect_keys({"set", "limit_strains", "order", "degree", "max_order", "symmetry"});
  if (auto v = b.find("set")) {
    const std::string set = v->string();
    if (set != "isotropic" && set != "anisotropic") v->fail("must be \"isotropic\" or \"anisotropic\"");
    scene.anisotropic = set == "anisotropic";
  }
  for (const char* key : scene.anisotropic ? std::vector<const char*>{"order"}
                                           : std::vector<const char*>{"degree", "max_order", "symmetry"})
    if (auto v = b.find(key)) v->fail(scene.anisotropic ? "is for the isotropic set" : "is for the anisotropic set");
  for (const SceneNode& s : b.at("limit_strains").items()) {
    if (scene.anisotropic) {
      scene.oriented_strains.push_back(s.vector(3));
    } else {
      scene.limit_strains.push_back(s.vector(2));
    }
  }
  if (auto o = b.find("order")) scene.order = o->integer(0);
  if (auto o = b.find("degree")) scene.degree = o->integer(0);
  scene.max_order = scene.degree;
  if (auto o = b.find("max_order")) scene.max_order = o->integer(0);
  if (auto sym = b.find("symmetry"))
    for (const SceneNode& s : sym->items()) {
      const std::string what = s.string();
      if (what == "reflect") {
        scene.symmetry.reflect = true;
      } else if (what == "swap") {
        scene.symmetry.swap = true;
      } else {
        s.fail("must be \"reflect\" (e_xy -> -e_xy) or \"swap\" (e_xx <-> e_yy)");
      }
    }
  try {
    (void)macro_strain_set(scene);
  } catch (const std::invalid_argument& e) {
    b.fail(e.what());
  }
  if (auto l = n.find("bending_limits")) {
    l->expect_keys({"limit_curvatures", "order", "barrier_stiffness", "barrier_activation"});
    for (const SceneNode& s : l->at("limit_curvatures").items()) {
      const Eigen::VectorXd v = s.vector(2);
      scene.bending_samples.emplace_back(v[0] * M_PI / 180.0, v[1]);
    }
    if (auto o = l->find("order")) scene.bending_order = o->integer(0);
    if (auto v = l->find("barrier_stiffness")) scene.drape.curvature_barrier.stiffness = v->positive();
    if (auto v = l->find("barrier_activation"))
      scene.drape.curvature_barrier.activation = v->open_interval(0.0, 1.0);
    try {
      scene.drape.bending_fit = interlocking::fit_bending_limits(scene.bending_samples, scene.bending_order);
    } catch (const std::invalid_argument& e) {
      l->fail(e.what());
    }
    scene.drape.bending_limits = true;
  }
  interlocking::DrapeSpec& d = scene.drape;
  if (auto m = n.find("material")) {
    m->expect_keys({"stiffness", "barrier_stiffness", "barrier_activation", "bending_stiffness"});
    if (auto v = m->find("stiffness")) d.material.stiffness = v->non_negative();
    if (auto v = m->find("barrier_stiffness")) d.material.barrier_stiffness = v->positive();
    if (auto v = m->find("barrier_activation")) d.material.barrier_activation = v->open_interval(0.0, 1.0);
    if (auto v = m->find("bending_stiffness")) d.bending_stiffness = v->non_negative();
  }
  if (auto s = n.find("drape")) {
    s->expect_keys({"width", "divisions", "areal_weight", "sphere_radius", "contact_activation",
                    "contact_stiffness", "max_iterations"});
    if (auto v = s->find("width")) d.width = v->positive();
    if (auto v = s->find("divisions")) {
      d.divisions = v->integer(2);
      if (d.divisions % 2 != 0) v->fail("must be even (a vertex at the sheet's centre)");
    }
    if (auto v = s->find("areal_weight")) d.areal_weight = v->non_negative();
    if (auto v = s->find("sphere_radius")) d.sphere_radius = v->positive();
    if (auto v = s->find("contact_activation")) d.contact_activation = v->positive();
    if (auto v = s->find("contact_stiffness")) d.contact_stiffness = v->positive();
    if (auto v = s->find("max_iterations")) d.newton.max_iterations = v->integer(1);
  }
  return scene;
}

bool run_interlocking_macro(const InterlockingMacroScene& scene, const std::string& out_dir,
                            std::ostream* log) {
  const auto t0 = std::chrono::steady_clock::now();
  const interlocking::MacroStrainSet set = macro_strain_set(scene);
  const ordered_json fit = fit_report(scene, set);
  if (log)
    *log << (set.anisotropic ? "anisotropic" : "isotropic") << " boundary fit: rms residual "
         << fit["rms_residual"].get<double>() << ", max " << fit["max_residual"].get<double>()
         << "; uniaxial limits at 0/45/90 degrees " << interlocking::macro_uniaxial_limit(set, 0.0) << " "
         << interlocking::macro_uniaxial_limit(set, M_PI / 4) << " " << interlocking::macro_uniaxial_limit(set, M_PI / 2)
         << "\n";
  const interlocking::DrapeResult r = interlocking::drape_over_sphere(set, scene.drape);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const bool ok = r.newton.converged() && r.margins.minCoeff() > 0.0 && r.gaps.minCoeff() > 0.0 &&
                  (!scene.drape.bending_limits || r.hinge_margins.minCoeff() > 0.0);
  std::filesystem::create_directories(out_dir);
  const int nv = r.flat.num_vertices();
  Eigen::MatrixX3d positions(nv, 3);
  for (int v = 0; v < nv; ++v) positions.row(v) = r.positions.segment<3>(3 * v).transpose();
  write_surface_vtu(out_dir + "/sheet.vtu", positions, r.flat.elements);
  Eigen::MatrixX3d sv;
  Eigen::MatrixX3i sf;
  sphere_surface(scene.drape.sphere_radius, 32, 64, sv, sf);
  write_surface_vtu(out_dir + "/sphere.vtu", sv, sf);
  write_fit_plot(out_dir + "/boundary_fit.png", scene.name + " boundary fit (e_xy = 0 section)", scene, set);
  const interlocking::MacroSheetMaterial& m = scene.drape.material;
  ordered_json bending = nullptr;
  if (scene.drape.bending_limits) {
    const interlocking::BendingLimitFit& bf = scene.drape.bending_fit;
    ordered_json bc = ordered_json::array();
    for (double c : bf.coefficients) bc.push_back(c);
    bending = {{"order", scene.bending_order},
               {"samples", bf.samples},
               {"fourier_coefficients", bc},
               {"rms_residual", bf.rms_residual},
               {"max_residual", bf.max_residual},
               {"min_limit", bf.min_limit},
               {"barrier_stiffness", scene.drape.curvature_barrier.stiffness},
               {"barrier_activation", scene.drape.curvature_barrier.activation},
               {"max_hinge_curvature", r.hinge_curvatures.maxCoeff()},
               {"min_hinge_margin", r.hinge_margins.minCoeff()}};
  }
  ordered_json report = {{"scene", scene.name},
                         {"status", ok ? "converged" : "failed"},
                         {"fit", fit},
                         {"bending_limits", bending},
                         {"material",
                          {{"stiffness", m.stiffness},
                           {"barrier_stiffness", m.barrier_stiffness},
                           {"barrier_activation", m.barrier_activation},
                           {"bending_stiffness", scene.drape.bending_stiffness}}},
                         {"newton",
                          {{"status", to_string(r.newton.status)},
                           {"message", r.newton.message},
                           {"iterations", r.newton.iterations},
                           {"final_residual", r.newton.final_residual},
                           {"energy", r.newton.final_energy}}},
                         {"drape",
                          {{"vertices", nv},
                           {"triangles", r.flat.num_elements()},
                           {"min_margin", r.margins.minCoeff()},
                           {"barrier_elements", r.barrier_elements},
                           {"max_principal_strain", r.principal_strains.col(0).maxCoeff()},
                           {"min_principal_strain", r.principal_strains.col(1).minCoeff()},
                           {"min_gap", r.gaps.minCoeff()},
                           {"contact_vertices", r.contact_vertices},
                           {"sagitta_bound", r.sagitta_bound},
                           {"lowest_z", r.positions(Eigen::seq(2, Eigen::last, 3)).minCoeff()}}},
                         {"files", {"sheet.vtu", "sphere.vtu", "boundary_fit.png"}},
                         {"seconds", seconds}};
  write_report(out_dir, report);
  if (log)
    *log << "drape: " << to_string(r.newton.status) << " in " << r.newton.iterations
         << " Newton iterations; margin >= " << r.margins.minCoeff() << " (" << r.barrier_elements << " of "
         << r.flat.num_elements() << " elements in the barrier's reach), " << r.contact_vertices
         << " vertices on the sphere, min gap " << r.gaps.minCoeff() << "\n";
  return ok;
}

}  // namespace tailor
