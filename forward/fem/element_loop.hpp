#pragma once
// The element loop of the simplicial energy terms (ElasticTerm, SplineElasticTerm): each term
// supplies its per-element math, the loop runs it over the covered elements in parallel,
// scatters the element gradients into the global gradient, writes the element Hessians to
// their slots and sums the energy.
//
// The loop runs colour by colour (LinearSimplices' colouring: no two elements of a colour share
// a vertex), a colour's chunks in parallel, each element adding its gradient straight into the
// global vector. Every gradient entry therefore receives its contributions in colour order and
// the energy is summed chunk by chunk in a fixed order: the result is the same on every run and
// for every thread count. The loop keeps no state between calls, so a term may be evaluated from
// several threads at once.
#include <Eigen/Core>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/fem/linear_simplices.hpp"

namespace tailor {

// What the loop asks of one element and where the element's results go.
template <int Dim>
struct ElementOutput {
  static constexpr int kLocal = LinearSimplices<Dim>::kLocal;
  using LocalHessian = Eigen::Map<Eigen::Matrix<double, kLocal, kLocal>>;
  bool want_gradient = false;
  bool want_hessian = false;
  HessianMode hessian_mode = HessianMode::exact;
  double energy = 0.0;                        // to set: V_e Psi_e
  Eigen::Matrix<double, kLocal, 1> gradient;  // to set when want_gradient: dE_e / dx_local
  double* hessian_slots = nullptr;            // the element's kLocal^2 slots (when want_hessian)
  // To set when want_hessian: d2E_e / dx_local^2 (symmetric, so row- and column-major agree
  // with the pattern's row-major slots).
  LocalHessian hessian() const { return LocalHessian(hessian_slots); }
};

// kernel(k, out): the energy (and, as out asks, gradient and Hessian) of covered element k.
// Small element sets (at most 256) run on the calling thread, in the same order.
template <int Dim, class Kernel>
void evaluate_elements(const LinearSimplices<Dim>& simplices, const EnergyRequest& request, const Kernel& kernel) {
  constexpr int kLocal = LinearSimplices<Dim>::kLocal;
  constexpr std::ptrdiff_t kSlots = kLocal * kLocal;
  const int colours = simplices.num_colours();
  std::vector<double> chunk_energy(static_cast<std::size_t>(simplices.num_chunks()), 0.0);
  Vector* const gradient = request.gradient;
#pragma omp parallel if (simplices.size() > 256)
  {
    ElementOutput<Dim> out;
    out.want_gradient = gradient != nullptr;
    out.want_hessian = request.hessian_values != nullptr;
    out.hessian_mode = request.hessian_mode;
    for (int c = 0; c < colours; ++c) {
#pragma omp for schedule(static)
      for (int j = simplices.colour_chunks[c]; j < simplices.colour_chunks[c + 1]; ++j) {
        double energy = 0.0;
        for (int i = simplices.chunk_begin[j]; i < simplices.chunk_begin[j + 1]; ++i) {
          const int k = simplices.colour_order[i];
          if (out.want_hessian) out.hessian_slots = request.hessian_values + k * kSlots;
          kernel(k, out);
          energy += out.energy;
          if (out.want_gradient)
            for (int a = 0; a <= Dim; ++a)
              gradient->template segment<Dim>(Dim * simplices.vertices[k][a]) +=
                  out.gradient.template segment<Dim>(Dim * a);
        }
        chunk_energy[j] = energy;
      }
    }
  }
  if (request.value) {
    double energy = 0.0;
    for (double e : chunk_energy) energy += e;
    *request.value += energy;
  }
}

}  // namespace tailor
