#pragma once
// The data layout and per-item steps of one pass of the vertex-block rule (docs/dynamics.md,
// "The GPU path"), shared by the host (forward/dynamics/descent_vertex_blocks.hpp runs each step
// in a loop) and the CUDA kernels (descent_cuda.cu runs one thread per item). The incremental
// potential, in the free unknowns y of a Dirichlet-only model, is
//   E(y) = sum_t E_t(x(y)) + e0 + g0.(y - y0) + 1/2 (y - y0)^T A (y - y0),
// the tets of the elastic terms plus the terms whose Hessian is constant (inertia, Rayleigh
// damping, gravity, loads) as their exact quadratic about the solve's start y0. Each step
// writes only its own item's outputs, and the per-vertex sums run through a precomputed
// vertex -> (tet, corner) incidence in a fixed order: no atomics, and the result does not
// depend on how items are scheduled.
#include "forward/dynamics/descent_tet_kernels.hpp"

namespace tailor::descent_kernels {

// Read-only arrays of the rule (device or host memory).
struct VertexBlockLayout {
  int material = kNeoHookean;
  int num_tets = 0;
  const int* tet_vertex = nullptr;     // 4 per tet: mesh vertices
  const double* tet_shape = nullptr;   // 12 per tet: rest shape gradients, row a = grad N_a
  const double* tet_volume = nullptr;  // rest volume [m^3]
  const double* tet_lame = nullptr;    // 2 per tet: lambda, mu [Pa]
  int num_blocks = 0;                  // vertices with a free unknown
  const int* block_vertex = nullptr;   // the vertex of each block
  const int* block_free = nullptr;     // 3 per block: free index of each component, -1 = fixed
  const int* incidence_begin = nullptr;  // num_blocks + 1
  const int* incidence = nullptr;        // 4 t + a: corner a of tet t touches the block
  const double* constant_blocks = nullptr;  // 9 per block: diagonal blocks of A
  int num_free = 0;
  const int* a_begin = nullptr;  // A as CSR over the free unknowns (both triangles)
  const int* a_col = nullptr;
  const double* a_value = nullptr;
  const double* g0 = nullptr;  // num_free
  const double* y0 = nullptr;  // num_free
};

// positions[3 v + k] = y[free] for the free components of block b (fixed ones stay).
TAILOR_HOST_DEVICE inline void scatter_block(const VertexBlockLayout& L, int b, const double* y, double* positions) {
  const int v = L.block_vertex[b];
  for (int k = 0; k < 3; ++k) {
    const int f = L.block_free[3 * b + k];
    if (f >= 0) positions[3 * v + k] = y[f];
  }
}

// Tet t at `positions`: its energy, 12 gradient values and (with_blocks) 4 projected blocks of 9.
TAILOR_HOST_DEVICE inline void tet_item(const VertexBlockLayout& L, int t, const double* positions, double* energy,
                                        double* gradient, double* blocks, bool with_blocks) {
  double x[12];
  for (int a = 0; a < 4; ++a) {
    const int v = L.tet_vertex[4 * t + a];
    for (int k = 0; k < 3; ++k) x[3 * a + k] = positions[3 * v + k];
  }
  energy[t] = tet_element(L.material, x, L.tet_shape + 12 * t, L.tet_volume[t], L.tet_lame[2 * t],
                          L.tet_lame[2 * t + 1], gradient + 12 * t, with_blocks ? blocks + 36 * t : nullptr, true);
}

// Row i of the constant part at y: its gradient g0_i + (A d)_i and its energy share
// (g0_i + (A d)_i / 2) d_i, d = y - y0 (summed over i with e0 this is the quadratic's value).
TAILOR_HOST_DEVICE inline void quadratic_row(const VertexBlockLayout& L, int i, const double* y, double* gradient,
                                             double* energy) {
  double Ad = 0.0;
  for (int s = L.a_begin[i]; s < L.a_begin[i + 1]; ++s) Ad += L.a_value[s] * (y[L.a_col[s]] - L.y0[L.a_col[s]]);
  gradient[i] = L.g0[i] + Ad;
  energy[i] = (L.g0[i] + 0.5 * Ad) * (y[i] - L.y0[i]);
}

// Block b: the reduced gradient of its free components (constant part + its tets' corners, in
// incidence order) and (with_blocks) the inverse of its preconditioner block (constant part +
// the tets' projected blocks; fixed components padded with the identity).
TAILOR_HOST_DEVICE inline void gather_block(const VertexBlockLayout& L, int b, const double* tet_gradient,
                                            const double* tet_blocks, const double* quadratic_gradient,
                                            double* gradient, double* inverse, bool with_blocks) {
  const int* free = L.block_free + 3 * b;
  double g[3] = {0, 0, 0}, B[9];
  if (with_blocks)
    for (int k = 0; k < 9; ++k) B[k] = L.constant_blocks[9 * b + k];
  for (int s = L.incidence_begin[b]; s < L.incidence_begin[b + 1]; ++s) {
    const int corner = L.incidence[s];  // 4 t + a
    for (int k = 0; k < 3; ++k) g[k] += tet_gradient[3 * corner + k];
    if (with_blocks)
      for (int k = 0; k < 9; ++k) B[k] += tet_blocks[9 * corner + k];
  }
  for (int k = 0; k < 3; ++k)
    if (free[k] >= 0) gradient[free[k]] = quadratic_gradient[free[k]] + g[k];
  if (!with_blocks) return;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (free[i] < 0 || free[j] < 0) B[3 * i + j] = i == j ? 1.0 : 0.0;
  block_inverse(B, 3, inverse + 9 * b);
}

// The preconditioned step and Chebyshev update of block b's free entries:
//   next = omega (u - alpha D^-1 g - previous) + previous.
TAILOR_HOST_DEVICE inline void chebyshev_block(const int* block_free, const double* inverse, int b,
                                               const double* gradient, const double* u, const double* previous,
                                               double alpha, double omega, double* next) {
  const int* free = block_free + 3 * b;
  const double* inv = inverse + 9 * b;
  double g[3];
  for (int j = 0; j < 3; ++j) g[j] = free[j] >= 0 ? gradient[free[j]] : 0.0;
  for (int i = 0; i < 3; ++i) {
    const int k = free[i];
    if (k < 0) continue;
    const double step = inv[3 * i] * g[0] + inv[3 * i + 1] * g[1] + inv[3 * i + 2] * g[2];
    next[k] = omega * (u[k] - alpha * step - previous[k]) + previous[k];
  }
}

}  // namespace tailor::descent_kernels
