// Newton on the periodic cell's contact barrier (see cell_equilibrium.hpp).
#include "forward/interlocking/cell_equilibrium.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/contact/barrier.hpp"
#include "forward/core/psd_projection.hpp"
#include "forward/interlocking/periodic_mesh_contact.hpp"
#include "forward/tori/torus.hpp"

namespace tailor::interlocking {

namespace {

tori::TorusPose body_pose(const PeriodicRigidCell& cell, int body, const Vector& x) {
  return {x.segment<3>(6 * body), x.segment<3>(6 * body + 3),
          cell.spec().elements[static_cast<std::size_t>(cell.master(body))].shape};
}

// The candidates within `range` with their distances (the contact term's close_pairs, over the
// broad phase's candidates).
std::vector<tori::TorusPair> close_candidates(const PeriodicRigidCell& cell, const Vector& x, double range,
                                              bool derivatives) {
  std::vector<tori::TorusPair> out;
  const tori::DistanceOptions& options = cell.contact().options().distance;
  for (const auto& [a, b] : cell.candidate_pairs(x, range)) {
    const tori::TorusPose pa = body_pose(cell, a, x), pb = body_pose(cell, b, x);
    const double reach = tori::bounding_radius(pa.shape) + tori::bounding_radius(pb.shape) + range;
    if ((pa.position - pb.position).norm() >= reach) continue;
    tori::TorusPair pair;
    pair.a = a;
    pair.b = b;
    pair.distance = tori::torus_distance(pa, pb, derivatives, options);
    if (pair.distance.distance < range) out.push_back(pair);
  }
  return out;
}

// B, dB/dx and the Hessian's triplets (12 x 12 per pair within d_hat) over the candidates.
void broad_phase_contact(const PeriodicRigidCell& cell, const Vector& x, double* energy, Vector* gradient,
                         Triplets* hessian, HessianMode mode) {
  const double d_hat = cell.activation_distance(), kappa = cell.contact().options().stiffness;
  const bool derivatives = gradient || hessian;
  double sum = 0.0;
  for (const tori::TorusPair& pair : close_candidates(cell, x, d_hat, derivatives)) {
    const contact::ScalarDerivatives e = tori::pair_barrier(pair.distance.distance, d_hat, kappa);
    sum += e.value;
    if (!derivatives || !std::isfinite(e.value)) continue;
    if (pair.distance.degenerate)
      throw std::runtime_error("periodic cell: bodies " + std::to_string(pair.a) + " and " + std::to_string(pair.b) +
                               " have a degenerate closest-point set (coaxial core circles): no derivatives");
    const Eigen::Matrix<double, 12, 1> g = e.first * pair.distance.gradient.head<12>();
    if (gradient) {
      gradient->segment<6>(6 * pair.a) += g.head<6>();
      gradient->segment<6>(6 * pair.b) += g.tail<6>();
    }
    if (hessian) {
      Eigen::Matrix<double, 12, 12> H =
          e.second * pair.distance.gradient.head<12>() * pair.distance.gradient.head<12>().transpose() +
          e.first * pair.distance.hessian.topLeftCorner<12, 12>();
      if (mode == HessianMode::projected) project_psd(H);
      const int ends[2] = {pair.a, pair.b};
      for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
          hessian->emplace_back(6 * ends[i / 6] + i % 6, 6 * ends[j / 6] + j % 6, H(i, j));
    }
  }
  if (energy) *energy += sum;
}

}  // namespace

std::vector<tori::TorusPair> contact_close_pairs(const PeriodicRigidCell& cell, const Vector& x, double range,
                                                 bool derivatives) {
  if (const PeriodicMeshContact* mesh = cell.mesh_contact()) return mesh->close_pairs(x, range);  // no derivatives
  if (!cell.spec().broad_phase || !std::isfinite(range))
    return cell.contact().close_pairs(x, cell.radii_parameters(), range, derivatives);
  return close_candidates(cell, x, range, derivatives);
}

std::vector<tori::TorusPairForce> contact_pair_forces(const PeriodicRigidCell& cell, const Vector& x) {
  if (const PeriodicMeshContact* mesh = cell.mesh_contact()) return mesh->pair_forces(x);
  if (!cell.spec().broad_phase) return cell.contact().pair_forces(x, cell.radii_parameters());
  std::vector<tori::TorusPairForce> out;
  const double d_hat = cell.activation_distance();
  for (const tori::TorusPair& pair : close_candidates(cell, x, d_hat, true)) {
    tori::TorusPairForce f;
    f.a = pair.a;
    f.b = pair.b;
    f.distance = pair.distance.distance;
    f.force_on_b = -tori::pair_barrier(f.distance, d_hat, cell.contact().options().stiffness).first *
                   pair.distance.gradient.segment<3>(6);
    out.push_back(f);
  }
  return out;
}

ReducedContact reduced_contact(const PeriodicRigidCell& cell, const Vector& x, bool hessian, HessianMode mode) {
  ReducedContact out;
  out.full_gradient = Vector::Zero(x.size());
  if (const PeriodicMeshContact* mesh = cell.mesh_contact()) {
    mesh->evaluate(x, &out.energy, &out.full_gradient, nullptr, mode);
    if (hessian && std::isfinite(out.energy)) mesh->evaluate(x, nullptr, nullptr, &out.full_hessian, mode);
  } else if (cell.spec().broad_phase) {
    Triplets triplets;
    broad_phase_contact(cell, x, &out.energy, &out.full_gradient, hessian ? &triplets : nullptr, mode);
    if (hessian && std::isfinite(out.energy)) {  // the Hessian only where the energy is finite
      out.full_hessian.resize(x.size(), x.size());
      out.full_hessian.setFromTriplets(triplets.begin(), triplets.end());
    }
  } else {
    const Vector p = cell.radii_parameters();
    EnergyRequest request;
    request.value = &out.energy;
    request.gradient = &out.full_gradient;
    cell.contact().evaluate(x, p, request);
    if (hessian && std::isfinite(out.energy)) out.full_hessian = cell.contact().hessian(x, p, mode);
  }
  out.gradient = cell.basis().transpose() * out.full_gradient;
  if (hessian && std::isfinite(out.energy)) {
    const SparseMatrix SH = cell.basis().transpose() * out.full_hessian;
    out.hessian = Matrix(SH * cell.basis());
  }
  return out;
}

double contact_energy(const PeriodicRigidCell& cell, const Vector& x) {
  double e = 0.0;
  if (const PeriodicMeshContact* mesh = cell.mesh_contact()) {
    mesh->evaluate(x, &e, nullptr, nullptr, HessianMode::exact);
  } else if (cell.spec().broad_phase) {
    broad_phase_contact(cell, x, &e, nullptr, nullptr, HessianMode::exact);
  } else {
    EnergyRequest request;
    request.value = &e;
    cell.contact().evaluate(x, cell.radii_parameters(), request);
  }
  return e;
}

double smallest_distance(const PeriodicRigidCell& cell, const Vector& x, double range) {
  if (const PeriodicMeshContact* mesh = cell.mesh_contact()) return mesh->min_distance(x, range);
  if (!cell.spec().broad_phase || !std::isfinite(range))
    return cell.contact().min_distance(x, cell.radii_parameters(), range);
  double best = std::numeric_limits<double>::infinity();
  for (const tori::TorusPair& pair : close_candidates(cell, x, range, false))
    best = std::min(best, pair.distance.distance);
  return best;
}

double contact_max_step(const PeriodicRigidCell& cell, const Vector& q, const Vector& dq) {
  if (const PeriodicMeshContact* mesh = cell.mesh_contact()) return mesh->max_step(q, dq);
  const tori::TorusContactTerm& term = cell.contact();
  if (!cell.spec().broad_phase) return term.max_step(q, dq);
  // TorusContactTerm::max_step's conservative advancement, pair by pair in the same order, over
  // the candidates (their grown spheres contain every pair whose spheres can meet along dq).
  ++term.ccd_calls;
  double alpha = 1.0;
  for (const auto& [a, b] : cell.candidate_pairs(q, 0.0, &dq)) {
    const tori::TorusShape& sa = cell.spec().elements[static_cast<std::size_t>(cell.master(a))].shape;
    const tori::TorusShape& sb = cell.spec().elements[static_cast<std::size_t>(cell.master(b))].shape;
    alpha = term.pair_max_step(a, b, sa, sb, q, dq, alpha);
    if (alpha == 0.0) return 0.0;
  }
  return alpha;
}

CellSolveResult levenberg_newton(const Vector& y_start, const CellSolveOptions& options, double smallest_step,
                                 const std::function<CellNewtonPoint(const Vector& y)>& point_at) {
  CellSolveResult result;
  result.y = y_start;
  for (int it = 0;; ++it) {
    const CellNewtonPoint c = point_at(result.y);
    result.energy = c.energy;
    result.iterations = it;
    if (!std::isfinite(c.energy)) {
      result.message = "the state intersects (infinite barrier)";
      return result;
    }
    result.residual = c.gradient.size() ? c.gradient.lpNorm<Eigen::Infinity>() : 0.0;
    if (result.residual <= options.force_tolerance) {
      result.converged = true;
      return result;
    }
    if (it >= options.max_iterations) {
      result.message = "Newton reached " + std::to_string(it) + " iterations, residual " + std::to_string(result.residual);
      return result;
    }
    // Levenberg: the shift mu = regularization (1 + max |H_ii|); where the step finds no decrease
    // (an ill-conditioned H, free elements swinging along near-null modes) it is retried with mu
    // 10^3 and 10^6 times larger, which turns it towards the gradient.
    const double mu0 = options.regularization * (1.0 + c.hessian.diagonal().cwiseAbs().maxCoeff());
    bool accepted = false;
    Vector dy;
    double alpha = 0.0;
    for (const double scale : {1.0, 1e3, 1e6}) {
      Matrix H = c.hessian;
      H.diagonal().array() += scale * mu0;
      dy = H.ldlt().solve(-c.gradient);
      alpha = std::min(1.0, c.max_step(dy));
      const double slope = c.gradient.dot(dy);
      for (int ls = 0; ls < options.max_line_search_steps && alpha > smallest_step; ++ls, alpha *= 0.5) {
        const double e = c.energy_along(alpha, dy);
        if (std::isfinite(e) && e <= c.energy + 1e-4 * alpha * slope) {
          accepted = true;
          break;
        }
      }
      if (accepted) break;
    }
    if (!accepted) {
      // The energy cannot resolve the decrease any more: accept the residual if it is small
      // relative to the force scale, else report the stall.
      result.message = "line search failed at residual " + std::to_string(result.residual);
      result.converged = result.residual <= std::sqrt(options.force_tolerance);
      return result;
    }
    result.y += alpha * dy;
  }
}

namespace {

CellSolveResult newton(const PeriodicRigidCell& cell, const Eigen::Matrix2d& F, const Vector& y_start,
                       const CellSolveOptions& options) {
  const Vector x0 = cell.offset(F);
  const SparseMatrix& S = cell.basis();
  return levenberg_newton(y_start, options, 0.0, [&](const Vector& y) {
    const Vector x = x0 + S * y;
    ReducedContact c = reduced_contact(cell, x, true, HessianMode::projected);
    CellNewtonPoint point{c.energy, std::move(c.gradient), std::move(c.hessian), {}, {}};
    point.max_step = [&cell, &S, x](const Vector& dy) { return contact_max_step(cell, x, S * dy); };
    point.energy_along = [&cell, &S, x](double alpha, const Vector& dy) {
      return contact_energy(cell, x + alpha * (S * dy));
    };
    return point;
  });
}

}  // namespace

CellSolveResult solve_cell_equilibrium(const PeriodicRigidCell& cell, const Eigen::Matrix2d& F,
                                       const Vector& y_start, const CellSolveOptions& options) {
  try {
    return newton(cell, F, y_start, options);
  } catch (const std::runtime_error& e) {  // a degenerate (coaxial) pair in contact
    CellSolveResult result;
    result.y = y_start;
    result.message = e.what();
    return result;
  }
}

}  // namespace tailor::interlocking
