#include "problems/rods/rod_inverse_statics.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "forward/core/assembler.hpp"
#include "problems/rods/rod_inverse.hpp"

namespace tailor {

std::string rod_inverse_statics_obstacle(const RodInverseSpec& spec, const RodSceneSpec& scene) {
  for (RodDesignBlock b : spec.design) {
    if (b == RodDesignBlock::radius || b == RodDesignBlock::youngs_modulus)
      return "the design includes " + to_string(b) + " (inverse statics designs rest strains only)";
    if (b == RodDesignBlock::rest_length && spec.per_rod)
      return "rest_length is designed per rod (inverse statics needs one rest length per edge)";
  }
  if (std::find(spec.design.begin(), spec.design.end(), RodDesignBlock::rest_curvature) == spec.design.end())
    return "the design does not include rest_curvature";
  if (scene.rods.size() != 1)
    return "the scene has " + std::to_string(scene.rods.size()) + " rods (inverse statics designs a lone rod)";
  const Eigen::MatrixX3d& drawn = scene.rods[static_cast<std::size_t>(spec.rod)].points;
  if (spec.components.size() != 3 || static_cast<Eigen::Index>(spec.target_vertices.size()) != drawn.rows())
    return "the target is not the drawn shape (every vertex, all three components)";
  std::vector<char> seen(static_cast<std::size_t>(drawn.rows()), 0);
  for (std::size_t i = 0; i < spec.target_vertices.size(); ++i) {
    const int v = spec.target_vertices[i];
    if (seen[static_cast<std::size_t>(v)] ||
        spec.target_positions.row(static_cast<Eigen::Index>(i)) != drawn.row(v))
      return "the target is not the drawn shape (vertex " + std::to_string(v) + ")";
    seen[static_cast<std::size_t>(v)] = 1;
  }
  return {};
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Which parameter each solved design variable sets, its index in z, and whether it is
// logarithmic (q = q0 exp(z)). The rest length of an edge whose two vertices are both held (a
// clamped edge) is left at z0: its stretching acts on no free DOF, and in the stencils next to
// it (through L_{i-1} + L_i) it only trades off against their rest curvature, so it would add a
// direction in which the design is not determined.
struct DesignColumns {
  std::vector<int> parameter, variable;
  std::vector<char> logarithmic;
};

DesignColumns design_columns(const RodInverseProblem& P) {
  const Model& model = *P.model.model;
  const SparseMatrix& S = model.elimination().basis();
  const Vector free_weight = S.cwiseAbs() * Vector::Ones(S.cols());
  const DiscreteRod& rod = *P.model.rods[static_cast<std::size_t>(P.spec.rod)];
  auto vertex_held = [&](int v) {
    for (int k = 0; k < 3; ++k)
      if (free_weight[rod.position_dof(v, k)] != 0.0) return false;
    return true;
  };
  DesignColumns c;
  int z = 0;
  for (RodDesignBlock b : P.spec.design) {
    const auto [offset, size] = rod_design_block_range(P.model, P.spec.rod, b);
    for (int j = 0; j < size; ++j, ++z) {
      if (b == RodDesignBlock::rest_length && vertex_held(j) && vertex_held(rod.edge_end(j))) continue;
      c.parameter.push_back(offset + j);
      c.variable.push_back(z);
      c.logarithmic.push_back(b == RodDesignBlock::rest_length ? 1 : 0);
    }
  }
  return c;
}

// dr/dz = S^T (d2E/dxdp) (dp/dz): the free rows of the mixed block, the designed columns,
// scaled by dq/dz (1 for angles, q for logarithmic variables).
SparseMatrix residual_jacobian(const RodInverseProblem& P, const DesignColumns& c, const Vector& x,
                               const Vector& p) {
  const Model& model = *P.model.model;
  const SparseMatrix mixed = model.mixed(x, p);
  const int nz = static_cast<int>(c.parameter.size());
  SparseMatrix select(mixed.cols(), nz);
  Triplets t;
  t.reserve(static_cast<std::size_t>(nz));
  for (int j = 0; j < nz; ++j) {
    const int q = c.parameter[static_cast<std::size_t>(j)];
    t.emplace_back(q, j, c.logarithmic[static_cast<std::size_t>(j)] ? p[q] : 1.0);
  }
  select.setFromTriplets(t.begin(), t.end());
  return SparseMatrix(model.elimination().basis().transpose() * (mixed * select));
}

}  // namespace

namespace {

RodStability stability_with(ReducedAssembler& assembler, const Model& model, const Vector& y, const Vector& p) {
  SparseMatrix hessian = assembler.hessian_pattern_matrix();
  assembler.evaluate(y, p, nullptr, nullptr, &hessian, HessianMode::exact);
  Vector row_sums = Vector::Zero(hessian.rows());  // ||H||_inf from the upper triangle
  for (int j = 0; j < hessian.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(hessian, j); e; ++e) {
      row_sums[e.row()] += std::abs(e.value());
      if (e.row() != j) row_sums[j] += std::abs(e.value());
    }
  RodStability s;
  const double h_norm = row_sums.size() ? row_sums.maxCoeff() : 0.0;
  s.residual_floor = std::numeric_limits<double>::epsilon() * h_norm *
                     (1.0 + model.elimination().expand(y).lpNorm<Eigen::Infinity>());
  if (hessian.rows() == 0) return s;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Upper> ldlt(hessian);
  if (ldlt.info() != Eigen::Success) {
    s.nonpositive_pivots = 1;  // a zero pivot: singular
    return s;
  }
  const Vector& d = ldlt.vectorD();
  s.smallest_pivot = d.minCoeff();
  s.largest_pivot = d.maxCoeff();
  s.nonpositive_pivots = static_cast<int>((d.array() <= 0.0).count());
  return s;
}

}  // namespace

RodStability rod_stability(const Model& model, const Vector& y, const Vector& p) {
  ReducedAssembler assembler(model);
  return stability_with(assembler, model, y, p);
}

RodInverseStaticsResult solve_rod_inverse_statics(const RodInverseProblem& P) {
  const auto t0 = std::chrono::steady_clock::now();
  if (const std::string why = rod_inverse_statics_obstacle(P.spec, P.scene); !why.empty())
    throw std::invalid_argument("inverse statics does not apply: " + why);
  const Model& model = *P.model.model;
  const Elimination& elimination = model.elimination();
  const Vector y = elimination.restrict_state(P.model.rest);
  const Vector x = elimination.expand(y);
  const DesignColumns columns = design_columns(P);
  ReducedAssembler assembler(model);

  RodInverseStaticsResult out;
  out.z = P.z0;
  Vector p = P.parameterization->apply(out.z), r;
  assembler.evaluate(y, p, nullptr, &r, nullptr);
  out.residual_initial = out.residual = r.norm();
  out.residuals.push_back(out.residual);

  // Gauss-Newton with columns scaled to unit norm (J = Jh D, D = diag |J_j|): the rest-length
  // columns (axial stiffness EA) and the curvature columns (EI / lbar^2) differ by 1e6 and more
  // in a thin strand. (Jh^T Jh + mu I) w = -Jh^T r, dz = D^-1 w, mu = 1e-13: it only decides
  // directions Jh does not see (a zero column stays put) and damps the others by less than
  // round-off. Stops when a step no longer gains a factor 10: the residual has reached its
  // round-off floor (or the system is inconsistent, which the check below sees).
  constexpr int kMaxSteps = 10;
  for (int step = 0; step < kMaxSteps && out.residual > 0.0; ++step) {
    SparseMatrix J = residual_jacobian(P, columns, x, p);
    Vector scale(J.cols());
    for (int j = 0; j < J.cols(); ++j) {
      const double n = J.col(j).norm();
      scale[j] = n > 0.0 ? n : 1.0;
    }
    J = J * scale.cwiseInverse().asDiagonal();
    SparseMatrix normal = SparseMatrix(J.transpose() * J);
    SparseMatrix shift(normal.rows(), normal.cols());
    shift.setIdentity();
    normal += 1e-13 * shift;
    Eigen::SimplicialLDLT<SparseMatrix> solver(normal);
    if (solver.info() != Eigen::Success) break;
    const Vector dz = Vector(solver.solve(Vector(J.transpose() * r))).cwiseQuotient(scale);
    Vector trial = out.z;
    for (std::size_t j = 0; j < columns.variable.size(); ++j) trial[columns.variable[j]] -= dz[static_cast<Eigen::Index>(j)];
    const Vector trial_p = P.parameterization->apply(trial);
    Vector trial_r;
    assembler.evaluate(y, trial_p, nullptr, &trial_r, nullptr);
    const double trial_residual = trial_r.norm();
    if (!(trial_residual < out.residual)) break;
    const bool stalled = trial_residual > 0.1 * out.residual;
    out.z = trial;
    p = trial_p;
    r = std::move(trial_r);
    out.residual = trial_residual;
    out.residuals.push_back(trial_residual);
    ++out.steps;
    if (stalled) break;
  }

  out.stability = stability_with(assembler, model, y, p);
  out.at_round_off = out.residual <= 10.0 * out.stability.residual_floor;

  std::ostringstream why;
  if (!out.at_round_off)
    why << "the drawn shape is not an equilibrium of any admissible rest shape: residual " << out.residual
        << " after " << out.steps << " steps, above 10 x its round-off floor " << out.stability.residual_floor;
  if (!out.stability.stable())
    why << (out.at_round_off ? "" : "; ") << "the equilibrium is not stable: the free Hessian's LDL^T has "
        << out.stability.nonpositive_pivots << " non-positive pivots (smallest " << out.stability.smallest_pivot
        << ")";
  if (out.accepted())
    why << "residual " << out.residual_initial << " -> " << out.residual << " (round-off floor "
        << out.stability.residual_floor << ") in " << out.steps << " steps; smallest pivot "
        << out.stability.smallest_pivot;
  out.message = why.str();
  out.seconds = seconds_since(t0);
  return out;
}

}  // namespace tailor
