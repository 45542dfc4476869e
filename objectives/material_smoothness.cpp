#include "objectives/material_smoothness.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace tailor {

Vector MaterialSmoothness::adjacency_weights(const Mesh& mesh, const Eigen::MatrixXi& pairs,
                                             AdjacencyWeighting weighting) {
  return element_adjacency_weights(mesh, pairs, weighting);
}

SparseMatrix MaterialSmoothness::laplacian(const Mesh& mesh, AdjacencyWeighting weighting) {
  return element_adjacency_laplacian(mesh, weighting);
}

MaterialSmoothness::MaterialSmoothness(const Mesh& mesh, int offset, double alpha, MaterialSmoothnessOptions options)
    : offset_(offset), size_(mesh.num_elements()), alpha_(alpha), options_(options) {
  if (offset_ < 0) throw std::invalid_argument("MaterialSmoothness: negative parameter offset " + std::to_string(offset_));
  if (!std::isfinite(alpha_) || alpha_ < 0) throw std::invalid_argument("MaterialSmoothness: alpha must be finite and >= 0");
  laplacian_ = laplacian(mesh, options_.weighting);  // validates the mesh
  pairs_ = element_adjacency(mesh);
  weights_ = adjacency_weights(mesh, pairs_, options_.weighting);
}

Vector MaterialSmoothness::field(const Vector& p) const {
  if (p.size() < offset_ + size_)
    throw std::invalid_argument("MaterialSmoothness: parameter vector of size " + std::to_string(p.size()) +
                                " does not hold the block [" + std::to_string(offset_) + ", " +
                                std::to_string(offset_ + size_) + ")");
  Vector s = p.segment(offset_, size_);
  if (!options_.logarithmic) return s;
  for (int e = 0; e < size_; ++e) {
    if (!(s[e] > 0))
      throw std::domain_error("MaterialSmoothness: log of non-positive parameter of element " + std::to_string(e));
    s[e] = std::log(s[e]);
  }
  return s;
}

double MaterialSmoothness::value(const Vector& x, const Vector& p) const {
  (void)x;
  const Vector s = field(p);
  return 0.5 * alpha_ * s.dot(laplacian_ * s);
}

void MaterialSmoothness::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const { (void)x, (void)p, (void)gx; }

// dJ/dq = alpha L s (identity) or alpha (L s) ./ q (log, chain rule ds/dq = 1/q).
void MaterialSmoothness::add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const {
  (void)x;
  const Vector s = field(p);
  const Vector Ls = alpha_ * (laplacian_ * s);
  if (options_.logarithmic)
    gp.segment(offset_, size_) += Ls.cwiseQuotient(p.segment(offset_, size_));
  else
    gp.segment(offset_, size_) += Ls;
}

// J_pp dq = alpha L dq (identity), or for s = log q:
//   J_pp dq = alpha [ (L (dq ./ q)) ./ q - (L s) .* dq ./ q.^2 ]
// (the second term from d(1/q)/dq; the Hessian is exact, not only its Gauss-Newton part).
void MaterialSmoothness::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp,
                                           Vector& out_x, Vector& out_p) const {
  (void)x, (void)dx, (void)out_x;
  const Vector s = field(p);
  const Vector dq = dp.segment(offset_, size_);
  if (!options_.logarithmic) {
    out_p.segment(offset_, size_) += alpha_ * (laplacian_ * dq);
    return;
  }
  const Vector q = p.segment(offset_, size_);
  const Vector ds = dq.cwiseQuotient(q);
  out_p.segment(offset_, size_) +=
      alpha_ * ((laplacian_ * ds).cwiseQuotient(q) - (laplacian_ * s).cwiseProduct(ds).cwiseQuotient(q));
}

void MaterialSmoothness::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                                   SparseMatrix* dr_dp) const {
  const Vector s = field(p);
  const int m = num_residuals();
  r.resize(m);
  Triplets triplets;
  triplets.reserve(2 * static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) {
    const int e = pairs_(k, 0), f = pairs_(k, 1);
    const double c = std::sqrt(alpha_ * weights_[k]);
    r[k] = c * (s[e] - s[f]);
    const double de = options_.logarithmic ? 1.0 / p[offset_ + e] : 1.0;
    const double df = options_.logarithmic ? 1.0 / p[offset_ + f] : 1.0;
    triplets.emplace_back(k, offset_ + e, c * de);
    triplets.emplace_back(k, offset_ + f, -c * df);
  }
  if (dr_dx) {
    dr_dx->resize(m, x.size());
    dr_dx->setZero();
  }
  if (dr_dp) {
    dr_dp->resize(m, p.size());
    dr_dp->setFromTriplets(triplets.begin(), triplets.end());
  }
}

}  // namespace tailor
