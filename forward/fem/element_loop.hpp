#pragma once
// The element loop of the simplicial energy terms (ElasticTerm, SplineElasticTerm on linear
// simplices, QuadraticElasticTerm on quadratic ones): each term
// supplies its per-element math, the loop runs it over the covered elements in parallel,
// writes the element Hessians to their slots, scatters the element gradients into the global
// gradient and sums the energy.
//
// Deterministic: the elements run in fixed chunks of consecutive elements (the same for every
// thread count), the energy is summed chunk by chunk in chunk order, and the element gradients
// (kept in a buffer of this call) are added to the global gradient in element order after the
// parallel part. So the result is the same on every run and for every thread count. The loop
// keeps no state between calls: a term may be evaluated from several threads at once.
#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/core/parallel_errors.hpp"

namespace tailor {

// What the loop asks of one element and where the element's results go. Nodes: nodes per
// element (Dim + 1 for linear simplices, 6 or 10 for quadratic triangles and tets).
template <int Dim, int Nodes = Dim + 1>
struct ElementOutput {
  static constexpr int kLocal = Dim * Nodes;
  using LocalGradient = Eigen::Map<Eigen::Matrix<double, Dim, Nodes>>;  // column a: node a
  using LocalHessian = Eigen::Map<Eigen::Matrix<double, kLocal, kLocal>>;
  bool want_gradient = false;
  bool want_hessian = false;
  HessianMode hessian_mode = HessianMode::exact;
  double energy = 0.0;              // to set: V_e Psi_e
  double* gradient_slots = nullptr;  // kLocal values (when want_gradient)
  double* hessian_slots = nullptr;   // kLocal^2 values (when want_hessian)
  // To set when want_gradient: dE_e / dx_a in column a.
  LocalGradient gradient() const { return LocalGradient(gradient_slots); }
  // To set when want_hessian: d2E_e / dx_local^2 (symmetric, so row- and column-major agree
  // with the pattern's row-major slots).
  LocalHessian hessian() const { return LocalHessian(hessian_slots); }
};

// kernel(k, out): the energy (and, as out asks, gradient and Hessian) of covered element k.
// Up to 256 elements run on the calling thread. An exception from the kernel (a material
// refusing its parameters) reaches the caller: that of the lowest chunk that threw.
// Elements: LinearSimplices<Dim> or anything with the same shape: kNodes, size() and
// vertices[k][a], the global node of local node a (kernel takes ElementOutput<Dim, kNodes>&).
template <int Dim, class Elements, class Kernel>
void evaluate_elements(const Elements& simplices, const EnergyRequest& request, const Kernel& kernel) {
  constexpr int kNodes = Elements::kNodes;
  constexpr int kLocal = Dim * kNodes;
  constexpr std::ptrdiff_t kSlots = kLocal * kLocal;
  constexpr int kChunk = 256;
  const int n = simplices.size();
  const int chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> chunk_energy(static_cast<std::size_t>(chunks), 0.0);
  Vector* const gradient = request.gradient;
  // The element gradients of this call (not initialized: every element writes its own).
  const std::unique_ptr<double[]> local(gradient ? new double[static_cast<std::size_t>(n) * kLocal] : nullptr);
  FirstError errors;
#pragma omp parallel for schedule(static) if (n > 256)
  for (int j = 0; j < chunks; ++j) try {
    ElementOutput<Dim, kNodes> out;
    out.want_gradient = gradient != nullptr;
    out.want_hessian = request.hessian_values != nullptr;
    out.hessian_mode = request.hessian_mode;
    double energy = 0.0;
    const int end = std::min(n, (j + 1) * kChunk);
    for (int k = j * kChunk; k < end; ++k) {
      if (out.want_gradient) out.gradient_slots = local.get() + static_cast<std::ptrdiff_t>(k) * kLocal;
      if (out.want_hessian) out.hessian_slots = request.hessian_values + k * kSlots;
      kernel(k, out);
      energy += out.energy;
    }
    chunk_energy[static_cast<std::size_t>(j)] = energy;
  } catch (...) {
    errors.capture(j);
  }
  errors.rethrow();
  if (request.value) {
    double energy = 0.0;
    for (double e : chunk_energy) energy += e;
    *request.value += energy;
  }
  if (gradient)
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < kNodes; ++a)
        gradient->template segment<Dim>(Dim * simplices.vertices[k][a]) +=
            Eigen::Map<const Eigen::Matrix<double, Dim, 1>>(local.get() + static_cast<std::ptrdiff_t>(k) * kLocal +
                                                            Dim * a);
}

}  // namespace tailor
