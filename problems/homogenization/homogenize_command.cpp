#include "problems/homogenization/homogenize_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/nonlinear_homogenization.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/homogenization/directional_plots.hpp"
#include "problems/homogenization/plate_command.hpp"
#include "problems/homogenization/rod_network_command.hpp"
#include "problems/json_text.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"

namespace tailor {
namespace {

const char* const kVoigt2[] = {"11", "22", "12"};
const char* const kVoigt3[] = {"11", "22", "33", "23", "13", "12"};

nlohmann::json engineering_constants_json(const Matrix& S, int dim) {
  nlohmann::json out;
  const auto axis = [dim](int k) { return plane_direction(dim, k, (k + 1) % dim, 0.0); };
  const char* names = "123";
  for (int i = 0; i < dim; ++i) {
    out[std::string("E") + names[i]] = directional_youngs_modulus(S, axis(i));
    for (int j = 0; j < dim; ++j)
      if (i != j) out[std::string("nu") + names[i] + names[j]] = poisson_ratio(S, axis(i), axis(j));
  }
  for (int i = 0; i < dim; ++i)
    for (int j = i + 1; j < dim; ++j)
      out[std::string("G") + names[i] + names[j]] = shear_modulus(S, axis(i), axis(j));
  return out;
}

}  // namespace

std::vector<DirectionalSamples> sample_directions(const Matrix& S, int count) {
  const int dim = S.rows() == 3 ? 2 : 3;
  std::vector<DirectionalSamples> out;
  const int planes[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  const char* const names[3] = {"xy", "yz", "zx"};
  for (int p = 0; p < (dim == 2 ? 1 : 3); ++p) {
    DirectionalSamples s;
    s.plane = names[p];
    for (int k = 0; k <= count; ++k) {
      const double theta = 2.0 * M_PI * k / count;
      const Vector d = plane_direction(dim, planes[p][0], planes[p][1], theta);
      const Vector n = plane_direction(dim, planes[p][0], planes[p][1], theta + M_PI / 2);
      s.angle.push_back(theta);
      s.youngs_modulus.push_back(directional_youngs_modulus(S, d));
      s.poisson_ratio.push_back(poisson_ratio(S, d, n));
    }
    out.push_back(std::move(s));
  }
  return out;
}

void write_cell_fields(const std::string& out_dir, const std::string& prefix, LinearCell& cell,
                       const LinearHomogenization& result, const Vector& youngs_modulus,
                       const std::vector<int>& element_phase) {
  const Mesh& mesh = cell.cell().mesh;
  const int dim = mesh.dim();
  const int nv = mesh.num_vertices();
  for (int I = 0; I < static_cast<int>(result.states.size()); ++I) {
    const Vector& x = result.states[I];
    const Vector affine = macro_offset(cell.cell(), unit_macro_strain(dim, I));
    VtkFields fields;
    Eigen::MatrixXd displacement(nv, dim), fluctuation(nv, dim);
    for (int v = 0; v < nv; ++v)
      for (int k = 0; k < dim; ++k) {
        displacement(v, k) = x[dim * v + k] - mesh.rest_positions(v, k);
        fluctuation(v, k) = x[dim * v + k] - affine[dim * v + k];
      }
    fields.point["displacement"] = displacement;
    fields.point["fluctuation"] = fluctuation;
    fields.cell["stress"] = cell.element_stresses(I);
    fields.cell["youngs_modulus"] = youngs_modulus;
    Eigen::MatrixXd phase(mesh.num_elements(), 1);
    for (int e = 0; e < mesh.num_elements(); ++e) phase(e, 0) = element_phase.empty() ? 0 : element_phase[e];
    fields.cell["phase"] = phase;
    const std::string name = dim == 2 ? kVoigt2[I] : kVoigt3[I];
    write_vtu(out_dir + "/" + prefix + name + ".vtu", mesh, fields);
  }
}

HomogenizeRun homogenize_scene(const CellScene& scene, const std::string& out_dir, std::ostream* log) {
  if (scene.rod_network) return homogenize_rod_network(scene, out_dir, log);
  if (scene.cell.periodic == std::vector<bool>{true, true, false})
    return homogenize_plate(scene, out_dir, log);
  const int dim = scene.cell.dim();
  LinearCell cell(scene.cell, scene.plane);
  const Vector E = scene.youngs_modulus(), nu = scene.poisson_ratio();
  HomogenizeRun run;
  run.result = cell.solve(E, nu);
  run.compliance = compliance(run.result.stiffness);
  std::filesystem::create_directories(out_dir);

  const auto samples = sample_directions(run.compliance, scene.directions);
  nlohmann::ordered_json report;
  add_report_header(report);
  report["status"] = "ok";
  report["scene"] = scene.name;
  report["dimension"] = dim;
  report["plane"] = dim == 3 ? "3d" : (scene.plane == PlaneMode::plane_stress ? "stress" : "strain");
  nlohmann::json order = nlohmann::json::array();
  for (int I = 0; I < voigt_size(dim); ++I) order.push_back(dim == 2 ? kVoigt2[I] : kVoigt3[I]);
  report["voigt_order"] = order;
  report["shear_convention"] = "engineering strains (gamma_ij = 2 eps_ij), plain stresses: sigma = C eps";
  report["stiffness"] = matrix_json(run.result.stiffness);
  report["compliance"] = matrix_json(run.compliance);
  report["symmetry_error"] = run.result.symmetry_error;
  report["engineering_constants"] = engineering_constants_json(run.compliance, dim);
  Eigen::VectorXd volumes = element_volumes(scene.cell.mesh);
  std::vector<double> fractions(scene.materials.size(), 0.0);
  for (int e = 0; e < scene.cell.mesh.num_elements(); ++e)
    fractions[scene.element_phase[e]] += volumes[e] / scene.cell.volume();
  report["volume_fractions"] = fractions;
  nlohmann::json directional = nlohmann::json::array();
  for (const auto& s : samples) {
    nlohmann::json angles = nlohmann::json::array();
    for (const double a : s.angle) angles.push_back(a * 180.0 / M_PI);
    directional.push_back({{"plane", s.plane},
                           {"angle_degrees", angles},
                           {"youngs_modulus", s.youngs_modulus},
                           {"poisson_ratio", s.poisson_ratio}});
  }
  report["directional"] = directional;
  report["mesh"] = {{"vertices", scene.cell.mesh.num_vertices()},
                    {"elements", scene.cell.mesh.num_elements()},
                    {"periodic_nodes", scene.cell.num_periodic_nodes()},
                    {"cell_volume", scene.cell.volume()},
                    {"lattice", matrix_json(scene.cell.lattice.transpose())}};
  report["timings"] = {{"assembly_seconds", run.result.assembly_seconds},
                       {"factorization_seconds", run.result.factorization_seconds},
                       {"solve_seconds", run.result.solve_seconds}};
  if (scene.stress_strain) {
    const StressStrainSpec& spec = *scene.stress_strain;
    nlohmann::json curves = nlohmann::json::array();
    LinePlot plot;
    plot.title = scene.name + ": uniaxial macro strain (" + to_string(spec.material) + ")";
    plot.x_label = "macro strain t, F = I + t d dT";
    plot.y_label = "P : d dT";
    const Rgb colours[4] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}};
    for (std::size_t k = 0; k < spec.directions.size(); ++k) {
      const Vector& d = spec.directions[k];
      NonlinearCell nonlinear(scene.cell, spec.material, E, nu);
      const std::vector<MacroResponse> path =
          macro_strain_path(nonlinear, d * d.transpose(), spec.max_strain, spec.steps);
      nlohmann::json curve;
      curve["direction"] = std::vector<double>(d.data(), d.data() + d.size());
      char label[96];
      std::snprintf(label, sizeof label, dim == 2 ? "d = (%.2f, %.2f)" : "d = (%.2f, %.2f, %.2f)", d[0], d[1],
                    dim == 3 ? d[2] : 0.0);
      LineSeries series{label, colours[k % 4], {}, {}};
      for (std::size_t i = 0; i < path.size(); ++i) {
        const double t = spec.max_strain * static_cast<double>(i) / spec.steps;
        const double stress = d.dot(path[i].stress * d);
        curve["strain"].push_back(t);
        curve["stress"].push_back(stress);
        curve["stress_tensor"].push_back(matrix_json(path[i].stress));
        curve["energy_density"].push_back(path[i].energy_density);
        curve["newton_iterations"].push_back(path[i].newton.iterations);
        series.x.push_back(t);
        series.y.push_back(stress);
      }
      curve["completed"] = path.size() == static_cast<std::size_t>(spec.steps) + 1;
      curves.push_back(curve);
      plot.series.push_back(std::move(series));
    }
    report["stress_strain"] = {{"material", to_string(spec.material)},
                               {"loading", "F = I + t d d^T (uniaxial macro strain), stress = P:(d d^T)"},
                               {"curves", curves}};
    write_line_plot_png(out_dir + "/stress_strain.png", plot);
  }
  const std::string report_path = write_report(out_dir, report);

  write_directional_plots(out_dir, scene.name, samples);
  write_cell_fields(out_dir, "load_case_", cell, run.result, E, scene.element_phase);

  if (log) {
    *log << "homogenized " << scene.name << ": " << scene.cell.mesh.num_elements() << " elements, "
         << scene.cell.num_periodic_nodes() << " periodic nodes; factorization "
         << run.result.factorization_seconds << " s, " << voigt_size(dim) << " solves "
         << run.result.solve_seconds << " s\n"
         << "C^H (Voigt " << (dim == 2 ? "11, 22, 12" : "11, 22, 33, 23, 13, 12") << ", engineering shear):\n"
         << std::setprecision(6) << run.result.stiffness << "\n"
         << "engineering constants: " << dump_json(report["engineering_constants"]) << "\n"
         << "wrote " << report_path << ", youngs_modulus_polar.png, poisson_ratio.png and load_case_*.vtu\n";
  }
  return run;
}

}  // namespace tailor
