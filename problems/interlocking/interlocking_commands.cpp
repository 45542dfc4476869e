// The verbs of interlocking scenes: boundary sweep, design gradcheck, design run (see
// interlocking_scene.hpp).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <ostream>

#include "forward/interlocking/interpenetration_check.hpp"
#include "forward/interlocking/periodic_mesh_contact.hpp"
#include "forward/interlocking/single_curvature_limit.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/torus.hpp"
#include "problems/contact/surface_vtu.hpp"
#include "problems/interlocking/interlocking_scene.hpp"
#include "problems/optimizer_report.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/report_file.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {
namespace {

using interlocking::LimitPoint;
using interlocking::PeriodicRigidCell;
using nlohmann::ordered_json;

// Every body of the cell (masters and images) as one surface at full state x.
void write_cell_vtu(const std::string& path, const PeriodicRigidCell& cell, const Vector& x) {
  Eigen::MatrixX3d vertices;
  Eigen::MatrixX3i faces;
  int nv = 0, nf = 0;
  std::vector<std::pair<Eigen::MatrixX3d, Eigen::MatrixX3i>> meshes;
  for (int body = 0; body < cell.num_bodies(); ++body) {
    Eigen::MatrixX3d v;
    Eigen::MatrixX3i f;
    const interlocking::CellElement& element = cell.spec().elements[static_cast<std::size_t>(cell.master(body))];
    if (element.mesh) {  // mesh bodies: the mesh the contact sees
      v = element.mesh->vertices;
      f = element.mesh->faces;
    } else {
      tori::torus_surface(element.shape, 32, 12, false, v, f);
    }
    const Eigen::Matrix3d Q = rigid::rotation_matrix(x.segment<3>(6 * body + 3));
    v = (v * Q.transpose()).rowwise() + x.segment<3>(6 * body).transpose();
    nv += static_cast<int>(v.rows());
    nf += static_cast<int>(f.rows());
    meshes.emplace_back(v, f);
  }
  vertices.resize(nv, 3);
  faces.resize(nf, 3);
  int ov = 0, of = 0;
  for (const auto& [v, f] : meshes) {
    vertices.middleRows(ov, v.rows()) = v;
    faces.middleRows(of, f.rows()) = f.array() + ov;
    ov += static_cast<int>(v.rows());
    of += static_cast<int>(f.rows());
  }
  write_surface_vtu(path, vertices, faces);
}

// The macro strain eps = (F + F^T)/2 - I of a limit (small-strain measure, reported as such).
Eigen::Matrix2d macro_strain(const Eigen::Matrix2d& F) {
  return 0.5 * (F + F.transpose()) - Eigen::Matrix2d::Identity();
}

ordered_json cell_json(const interlocking::RigidCellSpec& c, double d_hat) {
  ordered_json elements = ordered_json::array();
  for (const interlocking::CellElement& e : c.elements)
    elements.push_back({{"major_radius", e.shape.major_radius},
                        {"minor_radius", e.shape.minor_radius},
                        {"minor_radius_1", e.shape.minor_radius_1},
                        {"position", {e.position.x(), e.position.y(), e.position.z()}},
                        {"rotation", {e.rotation.x(), e.rotation.y(), e.rotation.z()}},
                        {"rim", e.rim}});
  for (std::size_t i = 0; i < c.elements.size(); ++i)
    if (const auto& mesh = c.elements[i].mesh)
      elements[i]["mesh"] = {{"source", mesh->source},
                             {"triangles", mesh->faces.rows()},
                             {"chordal_error", mesh->chordal_error}};
  return {{"elements", elements},
          {"bending_patch", c.bending_patch},
          {"lattice", {{c.lattice(0, 0), c.lattice(1, 0)}, {c.lattice(0, 1), c.lattice(1, 1)}}},
          {"image_rings", c.image_rings},
          {"activation_distance", d_hat}};
}

void write_boundary_plot(const std::string& path, const std::string& title, const std::string& loading,
                         const std::vector<LimitPoint>& points, bool bending) {
  LineSeries locked{"locked", {200, 30, 30}, {}, {}}, free{"free to max_strain", {120, 120, 120}, {}, {}};
  // Uniaxial: s along the direction, then (a second pass) along its opposite, so that the locked
  // outline runs once around the origin in angle order instead of jumping through it.
  for (int pass = 0; pass < (loading == "uniaxial" ? 2 : 1); ++pass)
    for (const LimitPoint& p : points) {
      // principal: the point (eps_xx, eps_yy); uniaxial: s along the direction (and its opposite).
      const Eigen::Matrix2d e = macro_strain(p.deformation);
      const double sign = pass == 0 ? 1.0 : -1.0;
      LineSeries& s = p.locked ? locked : free;
      s.x.push_back(loading == "uniaxial" ? sign * p.strain * std::cos(p.angle) : e(0, 0));
      s.y.push_back(loading == "uniaxial" ? sign * p.strain * std::sin(p.angle) : e(1, 1));
    }
  LinePlot plot;
  plot.title = title;
  // Bending patches: s is a curvature, the tensor K in place of eps.
  plot.x_label = loading == "uniaxial" ? "s cos(theta)" : (bending ? "kappa_xx" : "eps_xx");
  plot.y_label = loading == "uniaxial" ? "s sin(theta)" : (bending ? "kappa_yy" : "eps_yy");
  // A polar outline: each sample drawn as a short series of its own would crowd the legend, so
  // the locked points are joined in angle order and the curve closed.
  if (!locked.x.empty()) {
    locked.x.push_back(locked.x.front());
    locked.y.push_back(locked.y.front());
  }
  plot.series.push_back(locked);
  if (!free.x.empty()) plot.series.push_back(free);
  // A reference circle 5% outside the farthest point: both axes span the same range, and no
  // point sits on the frame.
  double reach = 0.0;
  for (const LineSeries* s : {&locked, &free})
    for (std::size_t i = 0; i < s->x.size(); ++i) reach = std::max(reach, std::hypot(s->x[i], s->y[i]));
  LineSeries circle{"radius " + std::to_string(1.05 * reach).substr(0, 6), {190, 190, 190}, {}, {}};
  for (int k = 0; k <= 96; ++k) {
    circle.x.push_back(1.05 * reach * std::cos(2.0 * M_PI * k / 96));
    circle.y.push_back(1.05 * reach * std::sin(2.0 * M_PI * k / 96));
  }
  plot.series.push_back(circle);
  plot.width = plot.height = 640;
  write_line_plot_png(path, plot);
}

struct BoundaryRun {
  std::vector<LimitPoint> points;
  ordered_json json;
  bool ok = true;
};

BoundaryRun sweep(const InterlockingScene& scene, const interlocking::RigidCellSpec& spec, const std::string& out_dir,
                  std::ostream* log) {
  BoundaryRun run;
  const PeriodicRigidCell cell(spec);
  const auto t0 = std::chrono::steady_clock::now();
  const Vector y_rest = interlocking::rest_equilibrium(cell, scene.boundary.options.solve);
  ordered_json samples = ordered_json::array();
  std::filesystem::create_directories(out_dir);
  int k = 0;
  std::vector<double> sample_seconds;
  for (const interlocking::LoadPath& path : scene.boundary.paths()) {
    const auto ts = std::chrono::steady_clock::now();
    const bool curved = scene.boundary.single_curvature;
    std::optional<interlocking::SingleCurvatureCell> bent;
    if (curved) bent.emplace(cell, path.angle);
    LimitPoint p = curved ? interlocking::find_single_curvature_limit(*bent, y_rest, scene.boundary.options)
                          : interlocking::find_limit(cell, path, y_rest, scene.boundary.options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
    sample_seconds.push_back(seconds);
    const Vector x = curved ? bent->full_state(p.y, p.strain) : cell.full_state(p.y, p.deformation);
    // Tori: certified clearance; mesh bodies: the exact triangle-triangle intersection test.
    interlocking::ClearanceReport clearance;
    interlocking::MeshIntersectionReport crossing;
    if (cell.mesh_contact())
      crossing = interlocking::check_mesh_intersections(cell, x);
    else
      clearance = interlocking::check_clearance(cell, x);
    const bool stalled = !p.locked && p.status != "free up to max_strain";
    if (stalled || (cell.mesh_contact() ? !crossing.apart() : !clearance.apart())) run.ok = false;
    const Eigen::Matrix2d e = macro_strain(p.deformation);  // bending patches: the curvature K
    const std::string measure = spec.bending_patch || curved ? "kappa_" : "eps_";
    ordered_json active = ordered_json::array();
    for (const interlocking::ActivePair& a : p.active)
      active.push_back({{"pair", a.label},
                        {"distance", a.distance},
                        {"force_on_b", {a.force_on_b.x(), a.force_on_b.y(), a.force_on_b.z()}}});
    ordered_json sample = {{"angle_degrees", p.angle * 180.0 / M_PI},
                           {"status", p.status},
                           {"locked", p.locked},
                           {"refined", p.refined},
                           {"strain", p.strain},
                           {"bracket", p.bracket},
                           {measure + "xx", e(0, 0)},
                           {measure + "yy", e(1, 1)},
                           {measure + "xy", e(0, 1)},
                           {"F", {{p.deformation(0, 0), p.deformation(0, 1)}, {p.deformation(1, 0), p.deformation(1, 1)}}},
                           {"min_distance", p.min_distance},
                           {"certified_clearance", clearance.min_lower},
                           {"clearance_elliptic_skipped", clearance.elliptic_skipped},
                           {"critical_pair", p.critical_a >= 0 ? cell.pair_label(p.critical_a, p.critical_b) : ""},
                           {"active_pairs", active},
                           {"solves", p.solves},
                           {"seconds", seconds}};
    if (cell.mesh_contact()) {
      sample.erase("certified_clearance");
      sample.erase("clearance_elliptic_skipped");
      sample["mesh_intersection_check"] = {{"triangle_pairs_tested", crossing.triangle_pairs},
                                           {"intersecting", crossing.intersecting}};
    }
    if (scene.boundary.vtu) {
      const std::string file = "sample_" + std::to_string(k) + ".vtu";
      write_cell_vtu(out_dir + "/" + file, cell, x);
      sample["vtu"] = file;
    }
    if (log)
      *log << "  " << p.angle * 180.0 / M_PI << " deg: " << p.status << ", s = " << p.strain
           << (p.refined ? " (refined)" : "") << ", " << p.active.size() << " active pairs, "
           << (cell.mesh_contact() ? "intersecting triangle pairs " + std::to_string(crossing.intersecting)
                                   : "clearance " + std::to_string(clearance.min_lower))
           << "\n";
    samples.push_back(sample);
    run.points.push_back(p);
    ++k;
  }
  std::vector<double> sorted = sample_seconds;
  std::sort(sorted.begin(), sorted.end());
  run.json = {{"cell", cell_json(spec, cell.activation_distance())},
              {"loading", scene.boundary.loading},
              {"shear", scene.boundary.shear},
              {"single_curvature", scene.boundary.single_curvature},
              {"lock_criterion",
               {{"smallest_distance_at_most", scene.boundary.options.lock_fraction * cell.activation_distance()},
                {"lock_fraction", scene.boundary.options.lock_fraction}}},
              {"tolerance", scene.boundary.options.tolerance},
              {"max_strain", scene.boundary.options.max_strain},
              {"samples", samples},
              {"median_seconds_per_sample", sorted.empty() ? 0.0 : sorted[sorted.size() / 2]},
              {"seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()},
              {"all_certified_apart", run.ok}};
  write_boundary_plot(out_dir + "/boundary.png",
                      scene.name + (spec.bending_patch || scene.boundary.single_curvature ? " curvature-space boundary"
                                                                                          : " strain-space boundary"),
                      scene.boundary.loading, run.points, spec.bending_patch || scene.boundary.single_curvature);
  return run;
}

}  // namespace

bool run_interlocking_boundary(const InterlockingScene& scene, const interlocking::RigidCellSpec& cell,
                               const std::string& out_dir, std::ostream* log) {
  if (log) *log << "strain-space boundary of " << scene.name << " (" << scene.boundary.directions << " "
                << scene.boundary.loading << " directions)\n";
  BoundaryRun run = sweep(scene, cell, out_dir, log);
  ordered_json report = {{"scene", scene.name}, {"boundary", run.json}};
  write_report(out_dir, report);
  return run.ok;
}

bool gradcheck_interlocking_design(const InterlockingScene& scene, const std::string& out_dir, unsigned seed,
                                   std::ostream* log) {
  const InterlockingDesignSpec& d = *scene.design;
  LimitDesignFunctional functional(scene.cell, d.variables, d.targets, scene.boundary.options);
  TaylorTestOptions options = d.gradcheck;
  options.seed = seed;
  const TaylorTestResult r = taylor_test(functional, functional.initial_design(), options);
  if (log) *log << "Taylor test of the limit design functional\n" << r.table() << to_string(r.status) << ": " << r.message << "\n";
  std::filesystem::create_directories(out_dir);
  ordered_json report = {{"scene", scene.name}, {"taylor", taylor_json(r)}};
  write_report_file(out_dir + "/gradcheck.json", report);
  return r.passed();
}

bool run_interlocking_design(const InterlockingScene& scene, const std::string& out_dir, std::ostream* log,
                             std::ostream* progress) {
  const InterlockingDesignSpec& d = *scene.design;
  LimitDesignFunctional functional(scene.cell, d.variables, d.targets, scene.boundary.options);
  const Vector z0 = functional.initial_design();
  const double T0 = functional.value(z0);
  const std::vector<double> limits0 = functional.limits();
  OptimizerOptions options = d.optimizer;
  options.progress = progress;
  const OptimizerResult result =
      minimize(functional, z0, functional.bounds(), functional.margin_constraints(d.margin, d.reach), options);
  const double T = functional.value(result.z);
  const std::vector<double> limits = functional.limits();
  // The fresh native-scale sweep of the designed cell (from its rest placement, no warm start).
  const interlocking::RigidCellSpec designed = functional.spec_at(result.z);
  BoundaryRun check = sweep(scene, designed, out_dir + "/designed", log);
  // The targets re-measured by fresh sweeps of their own paths.
  ordered_json targets = ordered_json::array();
  const PeriodicRigidCell cell(designed);
  const Vector y_rest = interlocking::rest_equilibrium(cell, scene.boundary.options.solve);
  bool ok = result.status != OptimizerStatus::failed && check.ok;
  for (std::size_t k = 0; k < d.targets.size(); ++k) {
    const LimitPoint fresh = interlocking::find_limit(cell, d.targets[k].path, y_rest, scene.boundary.options);
    targets.push_back({{"angle_degrees", d.targets[k].path.angle * 180.0 / M_PI},
                       {"target", d.targets[k].strain},
                       {"initial", limits0[k]},
                       {"designed", limits[k]},
                       {"fresh_sweep", fresh.strain},
                       {"fresh_locked", fresh.locked}});
    if (log)
      *log << "target " << d.targets[k].strain << " at " << d.targets[k].path.angle * 180.0 / M_PI
           << " deg: initial " << limits0[k] << ", designed " << limits[k] << ", fresh sweep " << fresh.strain << "\n";
  }
  ordered_json z = ordered_json::array(), z_start = ordered_json::array();
  for (int i = 0; i < z0.size(); ++i) {
    z_start.push_back(z0[i]);
    z.push_back(result.z[i]);
  }
  const FunctionalCounters& counters = functional.counters();
  ordered_json report = {{"scene", scene.name},
                         {"status", to_string(result.status)},
                         {"message", result.message},
                         {"backend", to_string(options.backend)},
                         {"objective_initial", T0},
                         {"objective", T},
                         {"design_initial", z_start},
                         {"design", z},
                         {"targets", targets},
                         {"designed_cell", cell_json(designed, cell.activation_distance())},
                         {"designed_boundary", check.json},
                         {"history", optimizer_history_json(result)},
                         {"seconds", result.seconds},
                         {"seconds_per_evaluation", counters.evaluations ? counters.forward_seconds / counters.evaluations : 0.0},
                         {"evaluations", counters.evaluations}};
  write_report(out_dir, report);
  if (log) *log << "design: " << to_string(result.status) << ", objective " << T0 << " -> " << T << "\n";
  return ok;
}

}  // namespace tailor
