// The small text files a scene names, each read through the scene parser as a user's file
// would be: observations ("vertex ux uy [uz]" per line, an inverse objective term), nodal
// forces ("vertex fx fy [fz]", loads.nodal_file), vertex lists (a "file" vertex selector) and
// per-element values (materials[].youngs_modulus_file, a ground-truth modulus field). Every
// input is tried in each of these roles.
#include "fuzz/fuzz_support.hpp"
#include "problems/fem/scene.hpp"

namespace {

using namespace tailor;

const std::string kMesh = R"("mesh": {"box": {"min": [0, 0, 0], "max": [1, 1, 1], "cells": [1, 1, 1]}})";
const std::string kMaterial =
    R"({"elements": "all", "model": "linear", "youngs_modulus": 1, "poisson_ratio": 0.3})";
const std::string kDesign = R"("design": {"parameter": "youngs_modulus", "granularity": "per_element"})";

// The scenes, with FILE standing for the input's path.
std::vector<std::string> scenes() {
  return {
      "{" + kMesh + R"(, "materials": [)" + kMaterial + R"(], "inverse": {)" + kDesign +
          R"(, "objective": [{"type": "observations", "file": "FILE"}]}})",
      "{" + kMesh + R"(, "materials": [)" + kMaterial + R"(], "loads": {"nodal_file": "FILE"}})",
      "{" + kMesh +
          R"(, "materials": [{"elements": "all", "model": "linear", "youngs_modulus_file": "FILE", "poisson_ratio": 0.3}]})",
      "{" + kMesh + R"(, "materials": [)" + kMaterial +
          R"(], "dirichlet": [{"vertices": {"file": "FILE"}}]})",
      "{" + kMesh + R"(, "materials": [)" + kMaterial + R"(], "inverse": {)" + kDesign +
          R"(, "objective": [{"type": "synthetic_observations", "vertices": {"list": [0]}, )" +
          R"("youngs_modulus": {"file": "FILE"}}]}})",
  };
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::string> templates = scenes();
  const std::string path = fuzz::write_input("data.txt", fuzz::as_text(data, size));
  for (std::string scene : templates) {
    scene.replace(scene.find("FILE"), 4, path);
    fuzz::expect_clean([&] { parse_scene(scene, "fuzz.json", ""); });
  }
  return 0;
}
