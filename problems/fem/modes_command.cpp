#include "problems/fem/modes_command.hpp"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "forward/fem/mass.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/fem/report.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;

// A full-space mode (interleaved) as a num_vertices x dim point field.
Eigen::MatrixXd point_field(const Vector& mode, int dim) {
  Eigen::MatrixXd field(mode.size() / dim, dim);
  for (Eigen::Index v = 0; v < field.rows(); ++v) field.row(v) = mode.segment(dim * v, dim).transpose();
  return field;
}

}  // namespace

ModesRun modes_scene(const Scene& scene, int count, const std::string& out_dir, std::ostream* log) {
  const auto start = std::chrono::steady_clock::now();
  require_linear_elements(scene, "modes");
  const StaticSetup setup = setup_static_scene(scene);
  if (setup.density.size() > 0 && setup.density.minCoeff() <= 0.0)
    throw SceneError(scene.source + ": materials: modal analysis needs a density > 0 in every material");
  const int free = setup.num_dofs() - static_cast<int>(setup.fixed_dofs.size());
  if (count < 1 || count > free - 7)
    throw SceneError(scene.source + ": --count " + std::to_string(count) + " must be in [1, " +
                     std::to_string(std::max(free - 7, 1)) + "] for this mesh");
  // Modes at rest: the supports hold their vertices at the rest positions.
  std::unique_ptr<Model> model = build_static_model(setup, 1.0);
  const Vector rest = setup.rest_state();
  model->elimination().set_offset(rest);
  const SparseMatrix mass = mass_matrix(setup.mesh, setup.density, MassLumping::consistent);
  if (log)
    *log << "modes of scene '" << scene.name << "' (" << scene.source << "): " << setup.mesh.num_vertices()
         << " vertices, " << setup.mesh.num_elements() << " elements, " << free << " free DOFs\n";
  ModalAnalysisOptions options;
  options.count = count;
  ModesRun run;
  run.modes = modal_analysis(*model, setup.dim(), rest, setup.parameters(), mass, options);
  run.total_mass = setup.density.dot(element_volumes(setup.mesh));
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + out_dir + "': " + error.message());
  run.report_path = (std::filesystem::path(out_dir) / "report.json").string();
  run.modes_path = (std::filesystem::path(out_dir) / "modes.vtu").string();

  const ModalAnalysis& m = run.modes;
  VtkFields fields;
  for (Eigen::Index j = 0; j < m.modes.cols(); ++j)
    fields.point["mode_" + std::to_string(j + 1)] = point_field(m.modes.col(j), setup.dim());
  for (Eigen::Index j = 0; j < m.rigid_modes.cols(); ++j)
    fields.point["rigid_mode_" + std::to_string(j + 1)] = point_field(m.rigid_modes.col(j), setup.dim());
  write_vtu(run.modes_path, setup.mesh, fields);

  Json report;
  add_report_header(report);
  report["kind"] = "modes";
  report["scene"] = {{"name", scene.name}, {"source", scene.source}};
  report["count"] = m.eigenvalues.size();
  report["frequencies_hz"] = to_json(m.frequencies);
  report["eigenvalues"] = to_json(m.eigenvalues);
  report["rigid_modes"] = m.rigid_modes.cols();
  report["rigid_eigenvalues"] = to_json(m.rigid_eigenvalues);
  report["total_mass"] = run.total_mass;
  report["mesh"] = {{"dim", setup.dim()},
                    {"vertices", setup.mesh.num_vertices()},
                    {"elements", setup.mesh.num_elements()},
                    {"free_dofs", free}};
  report["solver"] = {{"message", m.solve.message},
                      {"dense", m.solve.dense},
                      {"iterations", m.solve.iterations},
                      {"operator_applications", m.solve.operator_applications},
                      {"shift", m.solve.shift}};
  report["seconds"] = run.seconds;
  write_report_file(run.report_path, report);

  if (log) {
    *log << std::setprecision(6);
    if (m.rigid_modes.cols() > 0) *log << m.rigid_modes.cols() << " rigid-body modes set apart\n";
    for (Eigen::Index j = 0; j < m.frequencies.size(); ++j)
      *log << "mode " << j + 1 << ": " << m.frequencies[j] << " Hz\n";
    *log << "time " << std::fixed << std::setprecision(3) << run.seconds << " s; wrote " << run.report_path
         << " and " << run.modes_path << "\n"
         << std::defaultfloat;
  }
  return run;
}

}  // namespace tailor
