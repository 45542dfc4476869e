#include "problems/homogenization/plate_command.hpp"

#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "forward/homogenization/plate_bending.hpp"
#include "problems/plot/line_plot.hpp"
#include "problems/report_file.hpp"

namespace tailor {

HomogenizeRun homogenize_plate(const CellScene& scene, const std::string& out_dir, std::ostream* log) {
  const PlateBending plate =
      plate_bending_stiffness(scene.cell, scene.youngs_modulus(), scene.poisson_ratio());
  HomogenizeRun run;
  run.result.stiffness = plate.stiffness;
  run.result.factorization_seconds = plate.factorization_seconds;
  run.compliance = plate.stiffness.inverse();
  std::filesystem::create_directories(out_dir);

  nlohmann::json D = nlohmann::json::array();
  for (int i = 0; i < 3; ++i)
    D.push_back({plate.stiffness(i, 0), plate.stiffness(i, 1), plate.stiffness(i, 2)});
  LinePlot polar;
  polar.title = scene.name + ": bending stiffness b(d)";
  polar.x_label = "b cos(theta)";
  polar.y_label = "b sin(theta)";
  polar.width = 900;
  polar.height = 700;
  LineSeries curve{"b(d)", {31, 119, 180}, {}, {}};
  nlohmann::json angles = nlohmann::json::array(), values = nlohmann::json::array();
  double max_b = 0.0;
  for (int k = 0; k <= scene.directions; ++k) {
    const double theta = 2.0 * M_PI * k / scene.directions;
    const double b =
        directional_bending_stiffness(plate.stiffness, Vector{{std::cos(theta), std::sin(theta)}});
    angles.push_back(theta * 180.0 / M_PI);
    values.push_back(b);
    curve.x.push_back(b * std::cos(theta));
    curve.y.push_back(b * std::sin(theta));
    max_b = std::max(max_b, b);
  }
  LineSeries circle{"max b", {180, 180, 180}, {}, {}};
  for (int k = 0; k <= 180; ++k) {
    circle.x.push_back(max_b * std::cos(2.0 * M_PI * k / 180));
    circle.y.push_back(max_b * std::sin(2.0 * M_PI * k / 180));
  }
  polar.series = {circle, curve};
  write_line_plot_png(out_dir + "/bending_stiffness_polar.png", polar);

  nlohmann::json report;
  report["status"] = "ok";
  report["scene"] = scene.name;
  report["mode"] = "plate_bending";
  report["voigt_order"] = {"11", "22", "12"};
  report["curvature_convention"] = "engineering twist (2 kappa_12); energy per area 1/2 kappa^T D kappa";
  report["bending_stiffness"] = D;
  report["mid_plane"] = plate.mid_plane;
  report["directional_bending"] = {{"angle_degrees", angles}, {"bending_stiffness", values}};
  report["mesh"] = {{"vertices", scene.cell.mesh.num_vertices()},
                    {"elements", scene.cell.mesh.num_elements()},
                    {"periodic_nodes", scene.cell.num_periodic_nodes()}};
  report["timings"] = {{"factorization_seconds", plate.factorization_seconds}};
  const std::string path = write_report(out_dir, report);
  if (log)
    *log << "plate bending of " << scene.name << ": D (Voigt 11, 22, 12, engineering twist) =\n"
         << std::setprecision(6) << plate.stiffness << "\nwrote " << path
         << " and bending_stiffness_polar.png\n";
  return run;
}

}  // namespace tailor
