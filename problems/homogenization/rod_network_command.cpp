#include "problems/homogenization/rod_network_command.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/rod_network_cell.hpp"
#include "problems/homogenization/directional_plots.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/rods/rod_vtu.hpp"

namespace tailor {
namespace {

nlohmann::json rows_json(const Matrix& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < M.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < M.cols(); ++j) row.push_back(M(i, j));
    rows.push_back(row);
  }
  return rows;
}

// E1, E2, nu12, nu21, G12 of a 3 x 3 compliance, each divided by `scale` where a modulus.
nlohmann::json constants_json(const Matrix& S, double scale) {
  const Vector x = plane_direction(2, 0, 1, 0.0), y = plane_direction(2, 0, 1, M_PI / 2);
  return {{"E1", directional_youngs_modulus(S, x) / scale},
          {"E2", directional_youngs_modulus(S, y) / scale},
          {"nu12", poisson_ratio(S, x, y)},
          {"nu21", poisson_ratio(S, y, x)},
          {"G12", shear_modulus(S, x, y) / scale}};
}

}  // namespace

HomogenizeRun homogenize_rod_network(const CellScene& scene, const std::string& out_dir, std::ostream* log) {
  const RodNetworkScene& spec = *scene.rod_network;
  const RodNetwork& network = spec.network;
  RodNetworkCell cell(network);
  const RodNetworkHomogenization h = cell.solve();
  HomogenizeRun run;
  run.result.stiffness = h.stiffness;
  run.result.symmetry_error = h.symmetry_error;
  run.result.assembly_seconds = h.assembly_seconds;
  run.result.factorization_seconds = h.factorization_seconds;
  run.result.solve_seconds = h.solve_seconds;
  run.compliance = compliance(h.stiffness);
  std::filesystem::create_directories(out_dir);

  const auto samples = sample_directions(run.compliance, scene.directions);
  double bar_length = 0.0;
  for (int b = 0; b < static_cast<int>(network.bars.size()); ++b)
    bar_length += (network.bar_end(b) - network.bar_start(b)).norm();
  nlohmann::ordered_json report;
  add_report_header(report);
  report["status"] = "ok";
  report["scene"] = scene.name;
  report["mode"] = "rod_network";
  report["dimension"] = 2;
  report["voigt_order"] = {"11", "22", "12"};
  report["shear_convention"] = "engineering strains (gamma_ij = 2 eps_ij), plain stresses: N = C eps";
  report["stiffness_units"] =
      "force per length (membrane); C / depth is the modulus of a sheet of that depth";
  report["membrane_stiffness"] = rows_json(h.stiffness);
  report["compliance"] = rows_json(run.compliance);
  report["symmetry_error"] = h.symmetry_error;
  report["membrane_constants"] = constants_json(run.compliance, 1.0);
  if (spec.depth > 0.0) {
    report["depth"] = spec.depth;
    report["stiffness"] = rows_json(h.stiffness / spec.depth);
    report["engineering_constants"] = constants_json(run.compliance, spec.depth);
    report["relative_density"] =
        bar_length * M_PI * network.radius * network.radius / (network.cell_area() * spec.depth);
  }
  nlohmann::json directional = nlohmann::json::array();
  for (const auto& s : samples) {
    nlohmann::json angles = nlohmann::json::array();
    for (const double a : s.angle) angles.push_back(a * 180.0 / M_PI);
    directional.push_back({{"plane", s.plane},
                           {"angle_degrees", angles},
                           {"membrane_youngs_modulus", s.youngs_modulus},
                           {"poisson_ratio", s.poisson_ratio}});
  }
  report["directional"] = directional;
  report["network"] = {{"joints", network.joints.rows()},
                       {"bars", network.bars.size()},
                       {"edges_per_bar", network.edges_per_bar},
                       {"radius", network.radius},
                       {"youngs_modulus", network.youngs_modulus},
                       {"shear_modulus", network.shear_modulus},
                       {"slenderness", bar_length / network.bars.size() / network.radius},
                       {"cell_area", network.cell_area()},
                       {"lattice", rows_json(network.lattice.transpose())},
                       {"dofs", cell.model().num_dofs()},
                       {"unknowns", cell.num_free()}};
  report["timings"] = {{"assembly_seconds", h.assembly_seconds},
                       {"factorization_seconds", h.factorization_seconds},
                       {"solve_seconds", h.solve_seconds}};
  const std::string report_path = write_report(out_dir, report);
  write_directional_plots(out_dir, scene.name + " (membrane)", samples);
  std::vector<RodOutput> rods;
  for (std::size_t b = 0; b < cell.rods().size(); ++b)
    rods.push_back({cell.rods()[b].get(), cell.rod_blocks()[b]});
  const char* const names[3] = {"11", "22", "12"};
  for (int I = 0; I < 3; ++I)
    write_rods_vtu(out_dir + "/load_case_" + names[I] + ".vtu", rods, h.states[static_cast<std::size_t>(I)],
                   cell.parameters());
  if (log)
    *log << "homogenized the rod network " << scene.name << ": " << network.bars.size() << " bars of "
         << network.edges_per_bar << " edges, " << cell.num_free() << " unknowns; factorization "
         << h.factorization_seconds << " s, 3 solves " << h.solve_seconds << " s\n"
         << "membrane stiffness C (Voigt 11, 22, 12, engineering shear; force per length):\n"
         << std::setprecision(6) << h.stiffness << "\nwrote " << report_path
         << ", youngs_modulus_polar.png, poisson_ratio.png and load_case_*.vtu\n";
  return run;
}

}  // namespace tailor
