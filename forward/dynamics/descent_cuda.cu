// Device kernels of the descent solver (forward/dynamics/descent_cuda.hpp): one thread per
// item of the shared per-item steps (descent_vertex_block_kernels.hpp), and block reductions.
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "forward/dynamics/descent_cuda.hpp"

namespace tailor::cuda {
namespace dk = descent_kernels;
namespace {

constexpr int kThreads = 256;

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw std::runtime_error(std::string("descent on the GPU: ") + what + ": " +
                                                      cudaGetErrorString(status));
}

int grid(int n) { return (n + kThreads - 1) / kThreads; }

__global__ void scatter_kernel(dk::VertexBlockLayout L, const double* y, double* positions) {
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b < L.num_blocks) dk::scatter_block(L, b, y, positions);
}

__global__ void tet_kernel(dk::VertexBlockLayout L, const double* positions, double* energy, double* gradient,
                           double* blocks) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t < L.num_tets) dk::tet_item(L, t, positions, energy, gradient, blocks, true);
}

__global__ void quadratic_kernel(dk::VertexBlockLayout L, const double* y, double* gradient, double* energy) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < L.num_free) dk::quadratic_row(L, i, y, gradient, energy);
}

__global__ void gather_kernel(dk::VertexBlockLayout L, const double* tet_gradient, const double* tet_blocks,
                              const double* quadratic_gradient, double* gradient, double* inverse) {
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b < L.num_blocks) dk::gather_block(L, b, tet_gradient, tet_blocks, quadratic_gradient, gradient, inverse, true);
}

__global__ void chebyshev_kernel(int num_blocks, const int* block_free, const double* inverse, const double* gradient,
                                 const double* u, const double* previous, double alpha, double omega, double* next) {
  const int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b < num_blocks) dk::chebyshev_block(block_free, inverse, b, gradient, u, previous, alpha, omega, next);
}

// partial[blockIdx.x] = the block's sum of: a[i] (kind 0), a[i]^2 (1), (a[i] + b[i]) (c[i] - d[i]) (2),
// by a fixed shared-memory tree.
__global__ void reduce_kernel(int n, int kind, const double* a, const double* b, const double* c, const double* d,
                              double* partial) {
  __shared__ double s[kThreads];
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  double v = 0.0;
  if (i < n) v = kind == 0 ? a[i] : kind == 1 ? a[i] * a[i] : (a[i] + b[i]) * (c[i] - d[i]);
  s[threadIdx.x] = v;
  __syncthreads();
  for (int w = kThreads / 2; w > 0; w /= 2) {
    if (static_cast<int>(threadIdx.x) < w) s[threadIdx.x] += s[threadIdx.x + w];
    __syncthreads();
  }
  if (threadIdx.x == 0) partial[blockIdx.x] = s[0];
}

template <class T>
T* allocate(std::size_t n) {
  T* p = nullptr;
  check(cudaMalloc(&p, sizeof(T) * (n > 0 ? n : 1)), "cudaMalloc");
  return p;
}

template <class T>
T* copy_to_device(const T* host, std::size_t n) {
  T* p = allocate<T>(n);
  if (n > 0) check(cudaMemcpy(p, host, sizeof(T) * n, cudaMemcpyHostToDevice), "cudaMemcpy to the device");
  return p;
}

}  // namespace

struct VertexBlockDevice::Arrays {
  dk::VertexBlockLayout L;  // device pointers
  int num_dofs = 0, nnz = 0;
  std::vector<void*> owned;
  double *positions = nullptr, *tet_energy = nullptr, *tet_gradient = nullptr, *tet_blocks = nullptr;
  double *quadratic_gradient = nullptr, *quadratic_energy = nullptr;
  double* y[3] = {nullptr, nullptr, nullptr};  // roles by index: current, previous, trial
  int current = 0, previous = 1, trial = 2;
  double* gradient[2] = {nullptr, nullptr};  // evaluations of current (eval) and trial (1 - eval)
  double* inverse[2] = {nullptr, nullptr};
  int eval = 0;
  double* partial = nullptr;  // the reductions' per-block sums
  std::vector<double> host_partial;
  template <class T>
  T* own(T* p) {
    owned.push_back(p);
    return p;
  }
  // One pass at y[slot] into evaluation e: the three sums.
  Sums evaluate(int slot, int e) {
    const int nb = L.num_blocks, nt = L.num_tets, nf = L.num_free;
    if (nb > 0) scatter_kernel<<<grid(nb), kThreads>>>(L, y[slot], positions);
    if (nt > 0) tet_kernel<<<grid(nt), kThreads>>>(L, positions, tet_energy, tet_gradient, tet_blocks);
    if (nf > 0) quadratic_kernel<<<grid(nf), kThreads>>>(L, y[slot], quadratic_gradient, quadratic_energy);
    if (nb > 0)
      gather_kernel<<<grid(nb), kThreads>>>(L, tet_gradient, tet_blocks, quadratic_gradient, gradient[e], inverse[e]);
    const int gt = grid(nt), gf = grid(nf);
    if (nt > 0) reduce_kernel<<<gt, kThreads>>>(nt, 0, tet_energy, nullptr, nullptr, nullptr, partial);
    if (nf > 0) {
      reduce_kernel<<<gf, kThreads>>>(nf, 0, quadratic_energy, nullptr, nullptr, nullptr, partial + gt);
      reduce_kernel<<<gf, kThreads>>>(nf, 1, gradient[e], nullptr, nullptr, nullptr, partial + gt + gf);
    }
    check(cudaGetLastError(), "kernel launch");
    host_partial.resize(static_cast<std::size_t>(gt + 2 * gf));
    if (!host_partial.empty())
      check(cudaMemcpy(host_partial.data(), partial, sizeof(double) * host_partial.size(), cudaMemcpyDeviceToHost),
            "pass");
    Sums sums;
    for (int k = 0; k < gt; ++k) sums.elastic_energy += host_partial[k];
    for (int k = 0; k < gf; ++k) sums.quadratic_energy += host_partial[gt + k];
    for (int k = 0; k < gf; ++k) sums.gradient_squared += host_partial[gt + gf + k];
    return sums;
  }
};

bool device_available() {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

std::string device_name() {
  if (!device_available()) return "";
  cudaDeviceProp prop;
  int device = 0;
  if (cudaGetDevice(&device) != cudaSuccess || cudaGetDeviceProperties(&prop, device) != cudaSuccess) return "";
  return prop.name;
}

VertexBlockDevice::VertexBlockDevice(const dk::VertexBlockLayout& h, int num_dofs) : d_(new Arrays) {
  Arrays& a = *d_;
  a.num_dofs = num_dofs;
  a.nnz = h.a_begin[h.num_free];
  const std::size_t nt = static_cast<std::size_t>(h.num_tets), nb = static_cast<std::size_t>(h.num_blocks),
                    nf = static_cast<std::size_t>(h.num_free);
  dk::VertexBlockLayout& L = a.L;
  L = h;
  L.tet_vertex = a.own(copy_to_device(h.tet_vertex, 4 * nt));
  L.tet_shape = a.own(copy_to_device(h.tet_shape, 12 * nt));
  L.tet_volume = a.own(copy_to_device(h.tet_volume, nt));
  L.tet_lame = a.own(allocate<double>(2 * nt));
  L.block_vertex = a.own(copy_to_device(h.block_vertex, nb));
  L.block_free = a.own(copy_to_device(h.block_free, 3 * nb));
  L.incidence_begin = a.own(copy_to_device(h.incidence_begin, nb + 1));
  L.incidence = a.own(copy_to_device(h.incidence, static_cast<std::size_t>(h.incidence_begin[nb])));
  L.constant_blocks = a.own(allocate<double>(9 * nb));
  L.a_begin = a.own(copy_to_device(h.a_begin, nf + 1));
  L.a_col = a.own(copy_to_device(h.a_col, static_cast<std::size_t>(a.nnz)));
  L.a_value = a.own(allocate<double>(static_cast<std::size_t>(a.nnz)));
  L.g0 = a.own(allocate<double>(nf));
  L.y0 = a.own(allocate<double>(nf));
  a.positions = a.own(allocate<double>(static_cast<std::size_t>(num_dofs)));
  a.tet_energy = a.own(allocate<double>(nt));
  a.tet_gradient = a.own(allocate<double>(12 * nt));
  a.tet_blocks = a.own(allocate<double>(36 * nt));
  a.quadratic_gradient = a.own(allocate<double>(nf));
  a.quadratic_energy = a.own(allocate<double>(nf));
  for (double*& y : a.y) y = a.own(allocate<double>(nf));
  for (int e = 0; e < 2; ++e) {
    a.gradient[e] = a.own(allocate<double>(nf));
    a.inverse[e] = a.own(allocate<double>(9 * nb));
  }
  a.partial = a.own(allocate<double>(static_cast<std::size_t>(grid(h.num_tets) + 2 * grid(h.num_free))));
  set_parameters(h);
}

VertexBlockDevice::~VertexBlockDevice() {
  for (void* p : d_->owned) cudaFree(p);
}

void VertexBlockDevice::set_parameters(const dk::VertexBlockLayout& h) {
  const dk::VertexBlockLayout& L = d_->L;
  auto put = [](const double* to, const double* from, std::size_t n) {
    if (n > 0)
      check(cudaMemcpy(const_cast<double*>(to), from, sizeof(double) * n, cudaMemcpyHostToDevice), "parameters");
  };
  put(L.tet_lame, h.tet_lame, 2 * static_cast<std::size_t>(h.num_tets));
  put(L.constant_blocks, h.constant_blocks, 9 * static_cast<std::size_t>(h.num_blocks));
  put(L.a_value, h.a_value, static_cast<std::size_t>(d_->nnz));
}

VertexBlockDevice::Sums VertexBlockDevice::start(const dk::VertexBlockLayout& h, const double* positions) {
  Arrays& a = *d_;
  const std::size_t nf = static_cast<std::size_t>(h.num_free);
  auto put = [](const double* to, const double* from, std::size_t n) {
    if (n > 0) check(cudaMemcpy(const_cast<double*>(to), from, sizeof(double) * n, cudaMemcpyHostToDevice), "start");
  };
  put(a.positions, positions, static_cast<std::size_t>(a.num_dofs));
  put(a.L.g0, h.g0, nf);
  put(a.L.y0, h.y0, nf);
  put(a.y[a.current], h.y0, nf);
  put(a.y[a.previous], h.y0, nf);
  return a.evaluate(a.current, a.eval);
}

VertexBlockDevice::Sums VertexBlockDevice::try_step(double alpha, double omega) {
  Arrays& a = *d_;
  if (a.L.num_blocks > 0)
    chebyshev_kernel<<<grid(a.L.num_blocks), kThreads>>>(a.L.num_blocks, a.L.block_free, a.inverse[a.eval],
                                                         a.gradient[a.eval], a.y[a.current], a.y[a.previous], alpha,
                                                         omega, a.y[a.trial]);
  return a.evaluate(a.trial, 1 - a.eval);
}

double VertexBlockDevice::trapezoid_change() {
  Arrays& a = *d_;
  const int nf = a.L.num_free;
  if (nf == 0) return 0.0;
  reduce_kernel<<<grid(nf), kThreads>>>(nf, 2, a.gradient[a.eval], a.gradient[1 - a.eval], a.y[a.trial],
                                        a.y[a.current], a.partial);
  check(cudaGetLastError(), "kernel launch");
  a.host_partial.resize(static_cast<std::size_t>(grid(nf)));
  check(cudaMemcpy(a.host_partial.data(), a.partial, sizeof(double) * a.host_partial.size(), cudaMemcpyDeviceToHost),
        "trapezoid");
  double s = 0.0;
  for (const double v : a.host_partial) s += v;
  return 0.5 * s;
}

void VertexBlockDevice::accept() {
  Arrays& a = *d_;
  const int old_previous = a.previous;
  a.previous = a.current, a.current = a.trial, a.trial = old_previous;
  a.eval = 1 - a.eval;
}

void VertexBlockDevice::restart() {
  Arrays& a = *d_;
  if (a.L.num_free > 0)
    check(cudaMemcpy(a.y[a.previous], a.y[a.current], sizeof(double) * static_cast<std::size_t>(a.L.num_free),
                     cudaMemcpyDeviceToDevice),
          "restart");
}

void VertexBlockDevice::read(double* y) const {
  const Arrays& a = *d_;
  if (a.L.num_free > 0)
    check(cudaMemcpy(y, a.y[a.current], sizeof(double) * static_cast<std::size_t>(a.L.num_free),
                     cudaMemcpyDeviceToHost),
          "read");
}

void VertexBlockDevice::read_evaluation(double* gradient, double* block_inverse) const {
  const Arrays& a = *d_;
  if (a.L.num_free > 0)
    check(cudaMemcpy(gradient, a.gradient[a.eval], sizeof(double) * static_cast<std::size_t>(a.L.num_free),
                     cudaMemcpyDeviceToHost),
          "read");
  if (a.L.num_blocks > 0)
    check(cudaMemcpy(block_inverse, a.inverse[a.eval], sizeof(double) * 9 * static_cast<std::size_t>(a.L.num_blocks),
                     cudaMemcpyDeviceToHost),
          "read");
}

}  // namespace tailor::cuda
