#pragma once
// Outputs of a static run: DIR/report.json (the machine-readable summary that later tools
// read; its format is documented field by field in docs/scenes.md and stays stable) and
// DIR/result.vtu (the deformed mesh with per-vertex and per-element fields, for ParaView).
#include <string>

#include "forward/mesh/mesh_io.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/report_header.hpp"

namespace tailor {

// Wall-clock seconds of the parts of a run.
struct RunTimings {
  double total = 0.0;          // the whole run, up to (not including) writing report.json
  double setup = 0.0;          // mesh, selectors, loads and model construction
  double analysis = 0.0;       // symbolic factorization (once per load step)
  double assembly = 0.0;       // energy, gradient and Hessian assembly
  double factorization = 0.0;  // numeric factorizations
  double solve = 0.0;          // triangular solves
  double line_search = 0.0;    // energy evaluations of the line searches
  double output = 0.0;         // post-processing and writing result.vtu
};

// Throws std::runtime_error when the file cannot be written.
void write_report_json(const std::string& path, const Scene& scene, const StaticSetup& setup,
                       const StaticSolution& solution, const RunTimings& timings);

// The deformed mesh with point field "displacement" and cell fields "youngs_modulus",
// "poisson_ratio", "density", "stress" (first Piola-Kirchhoff, row-major), "region" (added by write_vtu) and
// "material" (index of the scene's material entry), plus `extra` fields (e.g. the inverse
// verbs' initial and true Young's moduli).
void write_result_vtu(const std::string& path, const StaticSetup& setup, const StaticSolution& solution,
                      const VtkFields& extra = {});

}  // namespace tailor
