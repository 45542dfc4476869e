#pragma once
// A small valid scene as JSON text, and a helper that edits it, for the problems tests.
#include <gtest/gtest.h>

#include <string>

namespace tailor::testing {

// A 2 x 1 x 1 box of linear tets (4 x 2 x 2 cells), E = 1000, nu = 0.3, pulled along x by a
// unit traction on x = 2. Supports remove rigid motions only (statically determinate): x = 0
// is a roller in x, vertex (0,0,0) is fixed in y and z, (0,1,0) in z and (0,0,1) in y, so the
// bar contracts freely sideways.
inline std::string small_box_scene() {
  return R"({
  "name": "box",
  "mesh": {"box": {"min": [0, 0, 0], "max": [2, 1, 1], "cells": [4, 2, 2]}},
  "materials": [
    {"elements": "all", "model": "linear", "youngs_modulus": 1000, "poisson_ratio": 0.3}
  ],
  "dirichlet": [
    {"vertices": {"plane": {"axis": "x", "value": 0}}, "components": [0]},
    {"vertices": {"list": [0]}, "components": [1, 2]},
    {"vertices": {"box": {"min": [0, 1, 0], "max": [0, 1, 0]}}, "components": [2]},
    {"vertices": {"box": {"min": [0, 0, 1], "max": [0, 0, 1]}}, "components": [1]}
  ],
  "loads": {
    "tractions": [{"faces": {"plane": {"axis": "x", "value": 2}}, "traction": [1, 0, 0]}]
  },
  "solver": {"load_steps": 1}
})";
}

// small_box_scene() with the first occurrence of `from` replaced by `to`.
inline std::string with(const std::string& from, const std::string& to,
                        std::string text = small_box_scene()) {
  const auto at = text.find(from);
  if (at == std::string::npos) {
    ADD_FAILURE() << "the scene text has no '" << from << "'";
    return text;
  }
  return text.replace(at, from.size(), to);
}

}  // namespace tailor::testing
