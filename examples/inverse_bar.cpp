// A user's own inverse problem against an installed tailor: a Neo-Hookean bar of two materials
// is clamped at x = 0 and pulled at x = 4; from the displacements of its surface vertices
// (synthesised from the true moduli) recover the Young's modulus of each half.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "problems/fem/study.hpp"

using namespace tailor;

int main() {
  const double true_moduli[2] = {1e5, 3e5};
  Study study;
  study.mesh_box({0, 0, 0}, {4, 1, 1}, {8, 2, 2})
      .material(select::element_box({0, 0, 0}, {2, 1, 1}), "neo_hookean", 3 * true_moduli[0], 0.3)
      .material(select::element_box({2, 0, 0}, {4, 1, 1}), "neo_hookean", true_moduli[1] / 3, 0.3)
      .fix(select::plane("x", 0))
      .traction(select::plane("x", 4), {1e4, 0, -5e2})
      .design({{"parameter", "youngs_modulus"}, {"granularity", "per_material"}, {"min", 1e3}, {"max", 1e8}})
      .objective({{"type", "synthetic_observations"},
                  {"vertices", select::boundary()},
                  {"youngs_modulus", {{"materials", {true_moduli[0], true_moduli[1]}}}}})
      .optimizer({{"backend", "nlopt_lbfgs"}, {"max_iterations", 500}, {"gradient_tolerance", 1e-13}});

  const TaylorTestResult taylor = study.taylor_test();  // of J(z) = J(log E_left, log E_right)
  std::printf("%s", taylor.table().c_str());
  if (!taylor.passed()) return 1;

  const InverseRun run = study.run("out/inverse_bar", &std::cout);  // report.json, result.vtu, plots
  const auto error = [&](int i) { return std::abs(run.design_values[i] / true_moduli[i] - 1); };
  return error(0) < 1e-6 && error(1) < 1e-6 ? 0 : 1;
}
