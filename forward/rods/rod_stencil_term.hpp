#pragma once
// RodStencilTerm: the assembly shared by the rod energies (private to forward/rods). Each term
// is a sum over stencils k of W(s_k(x_k), q_k), where x_k are the stencil's N DOFs, s_k its S
// strains (dual numbers: exact gradient and Hessian in x_k) and q_k its Q parameters. W is
// given with its first and second derivatives in (s, q), so by the chain rule
//   dE/dx   = W_s . ds/dx,           d2E/dx2 = ds/dx^T W_ss ds/dx + sum_a W_s[a] d2s_a/dx2,
//   dE/dq   = W_q,                   d2E/dxdq = ds/dx^T W_sq.
// Derived classes provide (CRTP, no virtual calls in the loops):
//   int num_stencils() const;
//   std::array<int, N> stencil_dofs(int k) const;
//   std::array<int, Q> stencil_parameters(int k) const;
//   std::array<Dual2<N>, S> strains(const Eigen::Matrix<double, N, 1>& local, int k) const;
//   std::array<Dual1<N>, S> strain_gradients(const Eigen::Matrix<double, N, 1>& local, int k) const;
//     (the same strains with first derivatives only: gradient requests without a Hessian, such
//     as the line search's first trial, and the mixed block, which needs ds/dx only)
//   Eigen::Matrix<double, S, 1> strain_values(const Eigen::Matrix<double, N, 1>& local, int k) const;
//     (the same strains without derivatives, for value-only requests such as line searches)
// The three orders give bit-identical values and first derivatives (forward/rods/low_order_duals.hpp).
//   void prepare(const Vector& x, int order) const;
//     (called before strains (order 2) and strain_gradients (order 1) at state x: per-edge
//     data the stencils share, such as the bend-twist stencils' edge frames; order
//     kProductHessians: what strain_gradients and strain_hessian_sum need)
// and optionally
//   Eigen::Matrix<double, N, N> strain_hessian_sum(const Local& local, int k,
//                                                 const Eigen::Matrix<double, S, 1>& w) const;
//     (sum_a w_a d2s_a/dx2 by a kernel of its own: Hessian assemblies then take the values and
//     gradients from strain_gradients, bit-identical to the other paths, and only this sum
//     from the kernel; set_product_hessian(false) sends them back to `strains`)
//   StencilEnergy<S, Q> energy_density(const Eigen::Matrix<double, S, 1>& s,
//                                      const Eigen::Matrix<double, Q, 1>& q, int k) const;
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/core/psd_projection.hpp"
#include "forward/rods/dual2_vec3.hpp"

namespace tailor::rod_detail {

template <int S, int Q>
struct StencilEnergy {
  double value = 0.0;
  Eigen::Matrix<double, S, 1> ds = Eigen::Matrix<double, S, 1>::Zero();
  Eigen::Matrix<double, S, S> dss = Eigen::Matrix<double, S, S>::Zero();
  Eigen::Matrix<double, Q, 1> dq = Eigen::Matrix<double, Q, 1>::Zero();
  Eigen::Matrix<double, S, Q> dsq = Eigen::Matrix<double, S, Q>::Zero();
};

// prepare()'s order for a Hessian assembly through strain_hessian_sum.
inline constexpr int kProductHessians = 3;

template <class Derived, int N, int S, int Q>
class RodStencilTerm : public EnergyTerm {
 public:
  using Local = Eigen::Matrix<double, N, 1>;
  using Strains = std::array<Dual2<N>, S>;
  using StrainGradients = std::array<Dual1<N>, S>;

  // Leaves stencil k out of the energy (a rigid joint at a rod's interior vertex replaces its
  // bending and twisting stencil there, forward/rods/rigid_joint_term.hpp); its Hessian block
  // stays in the pattern, with zeros.
  void omit_stencil(int k) {
    omitted_.resize(static_cast<std::size_t>(self().num_stencils()), 0);
    omitted_.at(static_cast<std::size_t>(k)) = 1;
  }
  bool omitted(int k) const { return !omitted_.empty() && omitted_[static_cast<std::size_t>(k)] != 0; }

  // Off: gradient requests run the strains on Dual2<N> (with their unused Hessians), as before
  // the Dual1 path existed (rod_bench's before/after comparison; the results are the same bit
  // for bit). Energy-only requests always take the plain-value path.
  void set_first_order_path(bool on) { first_order_path_ = on; }
  // Off: Hessian assemblies run `strains` (Hessians of every strain on dual numbers in the
  // stencil's variables, lifted to its N DOFs) instead of strain_hessian_sum, where the
  // term has one (rod_bench's before/after comparison; the Hessians agree to round-off).
  void set_product_hessian(bool on) { product_hessian_ = on; }

  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    const int num = self().num_stencils();
    const bool want_gradient = request.gradient != nullptr, want_hessian = request.hessian_values != nullptr;
    const bool product = want_hessian && uses_product_hessian();
    if (want_gradient) local_gradients_.resize(static_cast<std::size_t>(num) * N);
    if (product)
      self().prepare(x, kProductHessians);
    else if (want_hessian || (want_gradient && !first_order_path_))
      self().prepare(x, 2);
    else if (want_gradient)
      self().prepare(x, 1);
    double energy = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : energy) if (num > 512)
    for (int k = 0; k < num; ++k) {
      const auto dofs = self().stencil_dofs(k);
      if (omitted(k)) {
        if (want_gradient)
          std::fill(local_gradients_.data() + static_cast<std::size_t>(k) * N,
                    local_gradients_.data() + static_cast<std::size_t>(k + 1) * N, 0.0);
        if (want_hessian)
          std::fill(request.hessian_values + static_cast<std::size_t>(k) * N * N,
                    request.hessian_values + static_cast<std::size_t>(k + 1) * N * N, 0.0);
        continue;
      }
      if (!want_gradient && !want_hessian) {
        energy += self().energy_density(self().strain_values(gather(x, dofs), k), parameters(p, k), k).value;
        continue;
      }
      if (product) {
        const Local local = gather(x, dofs);
        const StrainGradients s = self().strain_gradients(local, k);
        const auto W = self().energy_density(values(s), parameters(p, k), k);
        energy += W.value;
        const Eigen::Matrix<double, S, N> J = jacobian(s);
        if (want_gradient) {
          Local g = Local::Zero();
          for (int a = 0; a < S; ++a) g += W.ds[a] * s[a].g;
          std::copy(g.data(), g.data() + N, local_gradients_.data() + static_cast<std::size_t>(k) * N);
        }
        Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
        if constexpr (has_product_hessian()) H = self().strain_hessian_sum(local, k, W.ds);
        H += J.transpose() * W.dss * J;
        H = 0.5 * (H + H.transpose()).eval();
        if (request.hessian_mode == HessianMode::projected) project_psd(H);
        std::copy(H.data(), H.data() + N * N, request.hessian_values + static_cast<std::size_t>(k) * N * N);
        continue;
      }
      if (!want_hessian && first_order_path_) {
        const StrainGradients s = self().strain_gradients(gather(x, dofs), k);
        const auto W = self().energy_density(values(s), parameters(p, k), k);
        energy += W.value;
        Local g = Local::Zero();
        for (int a = 0; a < S; ++a) g += W.ds[a] * s[a].g;
        std::copy(g.data(), g.data() + N, local_gradients_.data() + static_cast<std::size_t>(k) * N);
        continue;
      }
      const Strains s = self().strains(gather(x, dofs), k);
      const auto W = self().energy_density(values(s), parameters(p, k), k);
      energy += W.value;
      if (want_gradient) {
        Local g = Local::Zero();
        for (int a = 0; a < S; ++a) g += W.ds[a] * s[a].g;
        std::copy(g.data(), g.data() + N, local_gradients_.data() + static_cast<std::size_t>(k) * N);
      }
      if (want_hessian) {
        Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
        Eigen::Matrix<double, S, N> J;
        for (int a = 0; a < S; ++a) {
          J.row(a) = s[a].g.transpose();
          H += W.ds[a] * s[a].h;
        }
        H += J.transpose() * W.dss * J;
        H = 0.5 * (H + H.transpose()).eval();
        if (request.hessian_mode == HessianMode::projected) project_psd(H);
        std::copy(H.data(), H.data() + N * N, request.hessian_values + static_cast<std::size_t>(k) * N * N);
      }
    }
    if (request.value) *request.value += energy;
    if (want_gradient) {
      Vector& g = *request.gradient;
      for (int k = 0; k < num; ++k) {
        const auto dofs = self().stencil_dofs(k);
        for (int r = 0; r < N; ++r) g[dofs[r]] += local_gradients_[static_cast<std::size_t>(k) * N + r];
      }
    }
  }

  void hessian_pattern(HessianPattern& pattern) const override {
    const int num = self().num_stencils();
    pattern.reserve(pattern.size() + static_cast<std::size_t>(num) * N * N);
    for (int k = 0; k < num; ++k) {
      const auto dofs = self().stencil_dofs(k);
      for (int c = 0; c < N; ++c)
        for (int r = 0; r < N; ++r) pattern.push_back({dofs[r], dofs[c]});
    }
  }

  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override {
    for (int k = 0; k < self().num_stencils(); ++k) {
      if (omitted(k)) continue;
      const auto W =
          self().energy_density(self().strain_values(gather(x, self().stencil_dofs(k)), k), parameters(p, k), k);
      const auto params = self().stencil_parameters(k);
      for (int j = 0; j < Q; ++j) gradient_p[params[j]] += W.dq[j];
    }
  }

  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override {
    self().prepare(x, 1);
    for (int k = 0; k < self().num_stencils(); ++k) {
      if (omitted(k)) continue;
      const auto dofs = self().stencil_dofs(k);
      const StrainGradients s = self().strain_gradients(gather(x, dofs), k);
      const auto W = self().energy_density(values(s), parameters(p, k), k);
      const auto params = self().stencil_parameters(k);
      const Eigen::Matrix<double, N, Q> local = jacobian(s).transpose() * W.dsq;
      for (int r = 0; r < N; ++r)
        for (int j = 0; j < Q; ++j)
          if (local(r, j) != 0.0) mixed.emplace_back(dofs[r], params[j], local(r, j));
    }
  }

  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override {
    self().prepare(x, 1);
    for (int k = 0; k < self().num_stencils(); ++k) {
      if (omitted(k)) continue;
      const auto dofs = self().stencil_dofs(k);
      const StrainGradients s = self().strain_gradients(gather(x, dofs), k);
      const auto W = self().energy_density(values(s), parameters(p, k), k);
      const auto params = self().stencil_parameters(k);
      const Eigen::Matrix<double, Q, 1> local = W.dsq.transpose() * (jacobian(s) * gather(w, dofs));
      for (int j = 0; j < Q; ++j) gradient_p[params[j]] += local[j];
    }
  }

 protected:
  static Local gather(const Vector& x, const std::array<int, N>& dofs) {
    Local local;
    for (int r = 0; r < N; ++r) local[r] = x[dofs[r]];
    return local;
  }
  template <class Array>
  static Eigen::Matrix<double, S, 1> values(const Array& s) {
    Eigen::Matrix<double, S, 1> v;
    for (int a = 0; a < S; ++a) v[a] = s[a].v;
    return v;
  }
  template <class Array>
  static Eigen::Matrix<double, S, N> jacobian(const Array& s) {
    Eigen::Matrix<double, S, N> J;
    for (int a = 0; a < S; ++a) J.row(a) = s[a].g.transpose();
    return J;
  }
  Eigen::Matrix<double, Q, 1> parameters(const Vector& p, int k) const {
    const auto params = self().stencil_parameters(k);
    Eigen::Matrix<double, Q, 1> q;
    for (int j = 0; j < Q; ++j) q[j] = p[params[j]];
    return q;
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  // (A function: its body is instantiated where Derived is complete.)
  static constexpr bool has_product_hessian() {
    return requires(const Derived& d, const Local& l, const Eigen::Matrix<double, S, 1>& w) {
      d.strain_hessian_sum(l, 0, w);
    };
  }
  bool uses_product_hessian() const { return has_product_hessian() && product_hessian_; }
  mutable std::vector<double> local_gradients_;
  std::vector<char> omitted_;
  bool first_order_path_ = true;
  bool product_hessian_ = true;
};

}  // namespace tailor::rod_detail
