// Device kernels of the descent iteration's vector part (forward/dynamics/descent_cuda.hpp).
// One thread per block of 3 free unknowns: D^-1 g for its block, then the Chebyshev update of
// Wang & Yang 2016 (docs/dynamics.md, "The descent solver") for its entries.
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

#include "forward/dynamics/descent_cuda.hpp"

namespace tailor::cuda {
namespace {

__global__ void chebyshev_update_kernel(int num_blocks, const int* block_free, const double* block_inverse,
                                        const double* gradient, const double* u, const double* previous,
                                        double alpha, double omega, double* next) {
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b >= num_blocks) return;
  const int* free = block_free + 3 * b;
  const double* inv = block_inverse + 9 * b;
  double g[3];
  for (int j = 0; j < 3; ++j) g[j] = free[j] >= 0 ? gradient[free[j]] : 0.0;
  for (int i = 0; i < 3; ++i) {
    const int k = free[i];
    if (k < 0) continue;
    const double step = inv[3 * i] * g[0] + inv[3 * i + 1] * g[1] + inv[3 * i + 2] * g[2];
    next[k] = omega * (u[k] - alpha * step - previous[k]) + previous[k];
  }
}

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(status));
}

}  // namespace

bool device_available() {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

void chebyshev_update(int num_blocks, const int* block_free, const double* block_inverse, const double* gradient,
                      const double* u, const double* previous, double alpha, double omega, double* next) {
  const int threads = 256;
  const int grid = (num_blocks + threads - 1) / threads;
  if (grid == 0) return;
  chebyshev_update_kernel<<<grid, threads>>>(num_blocks, block_free, block_inverse, gradient, u, previous, alpha,
                                             omega, next);
  check(cudaGetLastError(), "descent chebyshev_update launch");
  check(cudaDeviceSynchronize(), "descent chebyshev_update");
}

void chebyshev_update_from_host(int num_blocks, int num_free, const int* block_free, const double* block_inverse,
                                const double* gradient, const double* u, const double* previous, double alpha,
                                double omega, double* next) {
  const std::size_t vector_bytes = sizeof(double) * static_cast<std::size_t>(num_free);
  int* d_free = nullptr;
  double *d_inverse = nullptr, *d_gradient = nullptr, *d_u = nullptr, *d_previous = nullptr, *d_next = nullptr;
  check(cudaMalloc(&d_free, sizeof(int) * 3 * static_cast<std::size_t>(num_blocks)), "cudaMalloc");
  check(cudaMalloc(&d_inverse, sizeof(double) * 9 * static_cast<std::size_t>(num_blocks)), "cudaMalloc");
  check(cudaMalloc(&d_gradient, vector_bytes), "cudaMalloc");
  check(cudaMalloc(&d_u, vector_bytes), "cudaMalloc");
  check(cudaMalloc(&d_previous, vector_bytes), "cudaMalloc");
  check(cudaMalloc(&d_next, vector_bytes), "cudaMalloc");
  check(cudaMemcpy(d_free, block_free, sizeof(int) * 3 * static_cast<std::size_t>(num_blocks), cudaMemcpyHostToDevice),
        "cudaMemcpy");
  check(cudaMemcpy(d_inverse, block_inverse, sizeof(double) * 9 * static_cast<std::size_t>(num_blocks),
                   cudaMemcpyHostToDevice),
        "cudaMemcpy");
  check(cudaMemcpy(d_gradient, gradient, vector_bytes, cudaMemcpyHostToDevice), "cudaMemcpy");
  check(cudaMemcpy(d_u, u, vector_bytes, cudaMemcpyHostToDevice), "cudaMemcpy");
  check(cudaMemcpy(d_previous, previous, vector_bytes, cudaMemcpyHostToDevice), "cudaMemcpy");
  check(cudaMemcpy(d_next, u, vector_bytes, cudaMemcpyHostToDevice), "cudaMemcpy");
  chebyshev_update(num_blocks, d_free, d_inverse, d_gradient, d_u, d_previous, alpha, omega, d_next);
  check(cudaMemcpy(next, d_next, vector_bytes, cudaMemcpyDeviceToHost), "cudaMemcpy");
  for (void* p : {static_cast<void*>(d_free), static_cast<void*>(d_inverse), static_cast<void*>(d_gradient),
                  static_cast<void*>(d_u), static_cast<void*>(d_previous), static_cast<void*>(d_next)})
    cudaFree(p);
}

}  // namespace tailor::cuda
