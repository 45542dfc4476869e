#pragma once
// The small handle scene of the reduced-design tests: a 5 x 1 x 1 cantilever (cells 8 x 2 x 2, 192
// tets) with a handle at the centre of its tip, 4 material modes; `extra` is appended to
// inverse.design.reduction (e.g. R"(, "smoothness": 1e-3)"); `solver`, when given, is the
// scene's "solver" object (e.g. R"({"hessian": "exact"})").
#include <string>

#include "problems/fem/scene.hpp"

namespace tailor {

inline std::string small_handle_scene_text(const std::string& model, const std::string& target,
                                           const std::string& extra = "", const std::string& solver = "") {
  return R"({
  "name": "small_handle_reduced",
  "mesh": {"box": {"min": [0, 0, 0], "max": [5, 1, 1], "cells": [8, 2, 2]}},
  "materials": [{"elements": "all", "model": ")" +
         model + R"(", "youngs_modulus": 1e6, "poisson_ratio": 0.3}],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],)" +
         (solver.empty() ? std::string() : "\n  \"solver\": " + solver + ",") + R"(
  "inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "modes", "modes": 4, "map": "identity",
               "reduction": {"displacement_modes": 4, "derivative_modes": 2)" +
         extra + R"(}},
    "objective": [{"type": "handles", "handles": [
      {"vertices": {"box": {"min": [5, 0.5, 0.5], "max": [5, 0.5, 0.5]}}, "force": [0, 0, -200],
       "displacement": )" +
         target + R"(}]}],
    "optimizer": {"backend": "nlopt_lbfgs", "max_iterations": 300, "gradient_tolerance": 1e-11,
                  "objective_tolerance": 1e-16}
  }
})";
}

inline Scene small_handle_scene(const std::string& model, const std::string& target = "[0, 0, -0.1]",
                                const std::string& extra = "", const std::string& solver = "") {
  return parse_scene(small_handle_scene_text(model, target, extra, solver), "small_handle_reduced.json", ".");
}

}  // namespace tailor
