#pragma once
// Where a descent iteration's arrays live and how its passes run (docs/dynamics.md, "The GPU
// path"): DescentSolver's loop (step control, Chebyshev weights, the rho estimate, stopping)
// runs on the host and asks a backend for the vector work, so the CPU and the device run the
// same loop. A backend holds three iterates (current u_k, previous u_{k-1}, trial) and the
// evaluations (energy, gradient, block inverses) of the current and the trial point.
//  - projected_hessian_backend: BlockJacobiPass on the host (the whole element tangent projected);
//  - vertex_block_host_backend: the vertex-block rule on the host (descent_vertex_blocks.hpp);
//  - make_device_backend (descent_device.hpp): the vertex-block rule on a CUDA device.
#include <functional>
#include <memory>
#include <string>

#include "forward/core/model.hpp"

namespace tailor {

class BlockJacobiPass;

class DescentBackend {
 public:
  struct Point {
    double energy = 0.0, energy_roundoff = 0.0;
    double residual = 0.0;  // ||g|| (reduced gradient)
  };
  virtual ~DescentBackend() = default;
  // Loads y as the current point (previous = current) and evaluates it, with the blocks.
  virtual Point start(const Vector& p, const Vector& y) = 0;
  // trial = omega (u - alpha D^-1 g - previous) + previous, evaluated with the blocks;
  // admissible: the model's terms accept the whole move from u (max_step >= 1).
  virtual Point try_step(double alpha, double omega, bool& admissible) = 0;
  // (g(u) + g(trial))^T (trial - u) / 2: the energy change by the trapezoidal rule.
  virtual double trapezoid_change() = 0;
  // previous <- u, u <- trial (with its evaluation).
  virtual void accept() = 0;
  // previous <- u (the acceleration restarts).
  virtual void restart() = 0;
  virtual void read(Vector& y) const = 0;
  // lambda_max(D^-1 H) at the current point by `iterations` steps of the power method, H the
  // exact reduced Hessian (power_largest_eigenvalue below).
  virtual double largest_eigenvalue(int iterations) = 0;
  virtual std::string device() const = 0;  // "cpu" or "gpu"
  virtual BlockJacobiPass* projected_pass() { return nullptr; }
};

// The power method on D^-1 H (similar to the symmetric D^-1/2 H D^-1/2, so its eigenvalues are
// real) from a fixed pseudo-random start: v <- D^-1 H v / ||D^-1 H v||; 0 when it breaks down.
double power_largest_eigenvalue(const Model& model, const Vector& p, const Vector& y, int iterations,
                                const std::function<void(const Vector&, Vector&)>& apply_inverse);

std::unique_ptr<DescentBackend> projected_hessian_backend(const Model& model, int block_size);
std::unique_ptr<DescentBackend> vertex_block_host_backend(const Model& model);

}  // namespace tailor
