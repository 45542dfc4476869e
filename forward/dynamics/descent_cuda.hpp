#pragma once
// The descent solver's passes and vector updates on a CUDA device (built only with
// TAILOR_HAVE_CUDA, cmake/tailorCuda.cmake; docs/dynamics.md, "The GPU path"), for the
// vertex-block rule (descent_vertex_block_kernels.hpp): the arrays of the rule and three
// iterates (current, previous, trial) with the evaluations of the current and the trial point
// stay on the device for a whole solve; a pass returns three sums (energy parts and ||g||^2),
// reduced per thread block in shared memory in a fixed tree and then on the host in block order,
// so results do not depend on scheduling. Plain C++ (no Eigen): g++ compiles the callers.
#include <memory>
#include <string>

#include "forward/dynamics/descent_vertex_block_kernels.hpp"

namespace tailor::cuda {

// Whether a CUDA device is usable by this process, and its name ("" when none).
bool device_available();
std::string device_name();

// The vertex-block rule's arrays and the solver's iterates on the device. Every call throws
// std::runtime_error with CUDA's message when the device fails.
class VertexBlockDevice {
 public:
  struct Sums {
    double elastic_energy = 0.0, quadratic_energy = 0.0;  // sum of tet energies; of the quadratic rows
    double gradient_squared = 0.0;                         // ||g||^2
  };
  // Copies the layout's fixed arrays (tets, blocks, incidence, A's pattern); num_dofs: length
  // of the positions.
  VertexBlockDevice(const descent_kernels::VertexBlockLayout& layout, int num_dofs);
  ~VertexBlockDevice();
  VertexBlockDevice(const VertexBlockDevice&) = delete;
  VertexBlockDevice& operator=(const VertexBlockDevice&) = delete;

  // Copies the parameter arrays (tet Lame parameters, A's values, the constant blocks).
  void set_parameters(const descent_kernels::VertexBlockLayout& layout);
  // A solve's start: positions (num_dofs), g0 and y0; current = previous = y0, evaluated.
  Sums start(const descent_kernels::VertexBlockLayout& layout, const double* positions);
  // trial = omega (u - alpha D^-1 g - previous) + previous, evaluated.
  Sums try_step(double alpha, double omega);
  // (g(u) + g(trial))^T (trial - u) / 2.
  double trapezoid_change();
  void accept();   // previous <- u, u <- trial
  void restart();  // previous <- u
  // The current iterate, its gradient (num_free) and block inverses (9 per block) to the host.
  void read(double* y) const;
  void read_evaluation(double* gradient, double* block_inverse) const;

 private:
  struct Arrays;
  std::unique_ptr<Arrays> d_;
};

}  // namespace tailor::cuda
