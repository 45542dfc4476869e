// The limit design functional (see limit_design.hpp).
#include "problems/interlocking/limit_design.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include <stdexcept>

#include "forward/tori/torus_distance.hpp"

namespace tailor {

using interlocking::PeriodicRigidCell;
using interlocking::RigidCellSpec;

std::vector<int> radius_entries(const RigidCellSpec& spec, const DesignVariable& variable) {
  std::vector<int> out;
  for (std::size_t i = 0; i < spec.elements.size(); ++i) {
    const int origin = spec.elements[i].origin >= 0 ? spec.elements[i].origin : static_cast<int>(i);
    if (origin == variable.element) out.push_back(2 * static_cast<int>(i) + (variable.major ? 0 : 1));
  }
  if (out.empty())
    throw std::invalid_argument("limit design: no element " + std::to_string(variable.element) + " in the cell");
  return out;
}

LimitDesignFunctional::LimitDesignFunctional(RigidCellSpec base, std::vector<DesignVariable> variables,
                                             std::vector<LimitTarget> targets, interlocking::LimitOptions options)
    : base_(std::move(base)), variables_(std::move(variables)), targets_(std::move(targets)), options_(options) {
  // Freeze d_hat at the base design's (the criterion's distance must not move with z).
  base_ = interlocking::with_parameters(base_, interlocking::master_radii(base_), base_.lattice);
  for (const DesignVariable& v : variables_) entries_.push_back(radius_entries(base_, v));
  states_.resize(targets_.size());
  limits_.assign(targets_.size(), 0.0);
}

Vector LimitDesignFunctional::initial_design() const {
  const Vector radii = interlocking::master_radii(base_);
  Vector z(size());
  for (int i = 0; i < size(); ++i) z[i] = radii[entries_[static_cast<std::size_t>(i)].front()];
  return z;
}

RigidCellSpec LimitDesignFunctional::spec_at(const Vector& z) const {
  Vector radii = interlocking::master_radii(base_);
  for (int i = 0; i < size(); ++i)
    for (const int e : entries_[static_cast<std::size_t>(i)]) radii[e] = z[i];
  return interlocking::with_parameters(base_, radii, base_.lattice);
}

Bounds LimitDesignFunctional::bounds() const {
  Bounds b;
  b.lower.resize(size());
  b.upper.resize(size());
  for (int i = 0; i < size(); ++i) {
    b.lower[i] = variables_[static_cast<std::size_t>(i)].lower;
    b.upper[i] = variables_[static_cast<std::size_t>(i)].upper;
  }
  return b;
}

double LimitDesignFunctional::value(const Vector& z) { return evaluate(z, nullptr); }

double LimitDesignFunctional::value_and_gradient(const Vector& z, Vector& gradient) {
  gradient.setZero(size());
  return evaluate(z, &gradient);
}

double LimitDesignFunctional::evaluate(const Vector& z, Vector* gradient) {
  const auto start = std::chrono::steady_clock::now();
  ++counters_.evaluations;
  std::unique_ptr<PeriodicRigidCell> cell;
  try {
    cell = std::make_unique<PeriodicRigidCell>(spec_at(z));
  } catch (const std::invalid_argument& e) {
    throw EvaluationError(std::string("limit design: ") + e.what());
  }
  const double lock = options_.lock_fraction * cell->activation_distance();
  double total = 0.0;
  Vector y_rest;
  for (std::size_t k = 0; k < targets_.size(); ++k) {
    PathState& state = states_[k];
    const interlocking::LoadPath& path = targets_[k].path;
    bool done = false;
    if (state.valid) {
      const interlocking::RefineResult r =
          interlocking::refine_limit(*cell, path, lock, state.a, state.b, state.y, state.strain);
      if (r.converged) {
        state.y = r.y;
        state.strain = r.strain;
        done = true;
      }
    }
    if (!done) {
      if (y_rest.size() == 0) y_rest = interlocking::rest_equilibrium(*cell, options_.solve);
      const interlocking::LimitPoint p = interlocking::find_limit(*cell, path, y_rest, options_);
      if (!p.locked || !p.refined)
        throw EvaluationError("limit design: path " + std::to_string(k) + " did not lock to a refined limit (" +
                              p.status + ")");
      state = {true, p.y, p.strain, p.critical_a, p.critical_b};
    }
    ++counters_.forward_solves;
    limits_[k] = state.strain;
    const double residual = state.strain - targets_[k].strain;
    total += 0.5 * residual * residual;
    if (gradient) {
      const interlocking::LimitGradient g =
          interlocking::limit_gradient(*cell, path, state.a, state.b, state.y, state.strain);
      ++counters_.adjoint_solves;
      for (int i = 0; i < size(); ++i)
        for (const int e : entries_[static_cast<std::size_t>(i)]) (*gradient)[i] += residual * g.radii[e];
    }
  }
  counters_.forward_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return total;
}

std::vector<Constraint> LimitDesignFunctional::margin_constraints(double margin, double reach) const {
  const PeriodicRigidCell cell(base_);
  const Vector x = cell.full_state(cell.rest_free_state(), Eigen::Matrix2d::Identity());
  std::vector<Constraint> out;
  // (Through the cell's broad phase: a patch's rim-rim pairs, which the contact term skips, count.)
  for (const tori::TorusPair& pair : interlocking::contact_close_pairs(cell, x, reach, false)) {
    Constraint c;
    c.name = "margin " + cell.pair_label(pair.a, pair.b);
    // The rest placement does not move with z: the poses are the base cell's, the shapes z's.
    const int ma = cell.master(pair.a), mb = cell.master(pair.b);
    tori::TorusPose pa{x.segment<3>(6 * pair.a), x.segment<3>(6 * pair.a + 3), {}};
    tori::TorusPose pb{x.segment<3>(6 * pair.b), x.segment<3>(6 * pair.b + 3), {}};
    const tori::DistanceOptions distance_options = cell.contact().options().distance;
    c.evaluate = [this, ma, mb, pa, pb, margin, distance_options](const Vector& z, Vector* gradient) mutable {
      const RigidCellSpec spec = spec_at(z);
      pa.shape = spec.elements[static_cast<std::size_t>(ma)].shape;
      pb.shape = spec.elements[static_cast<std::size_t>(mb)].shape;
      const tori::TorusDistance d = tori::torus_distance(pa, pb, gradient != nullptr, distance_options);
      if (gradient) {
        gradient->setZero(size());
        for (int i = 0; i < size(); ++i)
          for (const int index : entries_[static_cast<std::size_t>(i)]) {
            if (index / 2 == ma) (*gradient)[i] -= d.gradient[12 + index % 2];
            if (index / 2 == mb) (*gradient)[i] -= d.gradient[14 + index % 2];
          }
      }
      return margin - d.distance;
    };
    out.push_back(c);
  }
  return out;
}

}  // namespace tailor
