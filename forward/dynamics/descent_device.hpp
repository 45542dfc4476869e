#pragma once
// The descent solver's device backend (docs/dynamics.md, "The GPU path"): the vertex-block rule
// (descent_vertex_blocks.hpp) with its arrays and iterates on a CUDA device
// (descent_cuda.hpp). Compiled in every build; without CUDA it reports no device.
#include <memory>
#include <string>

#include "forward/dynamics/descent_backend.hpp"

namespace tailor {

// Whether this build has the CUDA path (cmake/tailorCuda.cmake).
bool built_with_cuda();
// Built with CUDA and a device present.
bool cuda_device_usable();
// The device's name, "" when none.
std::string cuda_device_name();

// Throws std::runtime_error when the build has no CUDA or no device is usable, and
// std::invalid_argument when the vertex-block rule does not cover the model.
std::unique_ptr<DescentBackend> make_device_backend(const Model& model);

}  // namespace tailor
