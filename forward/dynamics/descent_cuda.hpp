#pragma once
// The vector part of a descent iteration on a CUDA device (built only with TAILOR_HAVE_CUDA,
// cmake/tailorCuda.cmake): the block-Jacobi step and the Chebyshev update of
// forward/dynamics/descent_solver.hpp,
//   next = omega (u - alpha D^-1 g - previous) + previous,
// for blocks of 3 free unknowns (block_free: 3 free indices per block, -1 = padding;
// block_inverse: 9 row-major values per block). All pointers are device memory of the sizes
// BlockJacobiPass uses. Uncompiled and untested until a machine with nvcc and a GPU measures it
// (docs/dynamics.md, "The GPU path"); the element loop stays on the CPU.
namespace tailor::cuda {

// Whether a CUDA device is usable by this process.
bool device_available();

// Launches the update on the default stream and waits for it; throws std::runtime_error with
// CUDA's message on a failed launch.
void chebyshev_update(int num_blocks, const int* block_free, const double* block_inverse, const double* gradient,
                      const double* u, const double* previous, double alpha, double omega, double* next);

// The same from host arrays (num_free entries each, blocks as above): copies them to the
// device, runs the update and copies `next` back. For tests; a solver keeps its arrays on the
// device.
void chebyshev_update_from_host(int num_blocks, int num_free, const int* block_free, const double* block_inverse,
                                const double* gradient, const double* u, const double* previous, double alpha,
                                double omega, double* next);

}  // namespace tailor::cuda
