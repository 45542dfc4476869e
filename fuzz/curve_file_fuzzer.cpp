// Spline material curve files (JSON with "curves": uniaxial, biaxial, volumetric; what a
// material-fit run writes as material.json), read through a scene's spline material as
// {"curves": {"file": ...}}.
#include "fuzz/fuzz_support.hpp"
#include "problems/fem/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = tailor::fuzz::write_input("curves.json", tailor::fuzz::as_text(data, size));
  const std::string scene = R"({"mesh": {"box": {"min": [0, 0, 0], "max": [1, 1, 1], "cells": [1, 1, 1]}}, )"
                            R"("materials": [{"elements": "all", "model": "spline", "curves": {"file": ")" +
                            path + R"("}}]})";
  tailor::fuzz::expect_clean([&] { tailor::parse_scene(scene, "fuzz.json", ""); });
  return 0;
}
