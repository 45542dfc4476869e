#pragma once
// Parameterizations map design variables z to model parameters p = phi(z), with the products
// the adjoint needs: dphi/dz dz (direct mode) and dphi/dz^T w (reverse mode), plus the
// second-order term (d/dz [dphi/dz^T w]) dz for Hessian-vector products. They compose.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

class Parameterization {
 public:
  virtual ~Parameterization() = default;
  virtual std::string name() const = 0;
  virtual int num_design() const = 0;  // size of z
  virtual int num_params() const = 0;  // size of p
  virtual Vector apply(const Vector& z) const = 0;
  virtual Vector jacobian_times(const Vector& z, const Vector& dz) const = 0;            // (dp/dz) dz
  virtual Vector jacobian_transpose_times(const Vector& z, const Vector& w) const = 0;  // (dp/dz)^T w
  // sum_i w_i d2p_i/dz2 dz; zero for maps linear in z.
  virtual Vector second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const;
  // The dense Jacobian (for tests and small problems).
  Matrix jacobian(const Vector& z) const;
};

using ParameterizationPtr = std::shared_ptr<const Parameterization>;

// p = z.
ParameterizationPtr identity_map(int n);
// p_i = exp(z_i): positivity (and a log-scale for moduli spanning decades).
ParameterizationPtr exp_map(int n);
// p_i = s_i z_i, s_i finite and non-zero: variables in units of a characteristic size.
ParameterizationPtr scale_map(Vector scales);
// p = basis z + offset (e.g. Laplacian material modes: E = Phi z).
ParameterizationPtr linear_basis_map(Matrix basis, Vector offset);
// p_e = z[region[e]]: one design variable per region, scattered to its elements.
ParameterizationPtr region_scatter_map(std::vector<int> region_of_entry, int num_regions);
// p_i = lower_i + (upper_i - lower_i) * (1 + tanh(z_i)) / 2: strictly inside (lower, upper).
ParameterizationPtr bounds_map(Vector lower, Vector upper);
// p_i = s(t_i), s the natural cubic spline through control values z at increasing knots.
ParameterizationPtr spline_map(Vector knots, Vector sample_points);
// p = outer(inner(z)).
ParameterizationPtr compose(ParameterizationPtr outer, ParameterizationPtr inner);
// The full parameter vector: p = base, with p[offset_k : offset_k + size_k] = block_k(z_k),
// z = [z_1, z_2, ...] (e.g. design the Young's moduli while Poisson's ratios stay fixed).
struct ParameterBlock {
  int offset;
  ParameterizationPtr map;
};
ParameterizationPtr embed_blocks(Vector base, std::vector<ParameterBlock> blocks);

}  // namespace tailor
