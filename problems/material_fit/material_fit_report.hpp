#pragma once
// DIR/report.json of a material fit (`kind`: `material_fit`), laid out like the other reports
// (report.hpp, inverse_report.hpp: tailor_version, report_format, scene, status, history,
// objective, solves, timings, mesh) plus the fit's own fields; documented in docs/materials.md.
#include <string>

#include "forward/mesh/mesh.hpp"
#include "problems/material_fit/material_fit.hpp"

namespace tailor {

// The plot of one load case: "force_<name>.png".
std::string force_plot_name(const LoadCase& load_case);

// Throws std::runtime_error when the file cannot be written.
void write_material_fit_report(const std::string& path, const MaterialFitSpec& spec,
                               const MaterialFitRun& run, const PrincipalStretchCurves& fitted,
                               const Mesh& specimen);

}  // namespace tailor
