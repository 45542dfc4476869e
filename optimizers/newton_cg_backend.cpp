// Trust-region Newton-CG (Steihaug 1983, Toint 1981) with box bounds by projection: a truncated
// Newton method whose only second-order information is the functional's curvature products
// (Gauss-Newton products for least-squares objectives, exact Hessian-vector products, or, for
// functionals with neither, forward differences of gradients; see CurvatureProducts). For a
// simulation-backed functional (StaticFunctional) a product costs two back-solves with the
// factorization of the forward solve at the same design, so an iteration costs one
// factorization plus the back-solves of its CG iterations, where a quasi-Newton method pays a
// factorization for every one of its (many more) iterations.
//
// One iteration at the feasible z with gradient g and trust radius D:
//  1. Active set (Bertsekas' epsilon-active set): variables within eps = min(1e-3, ||z - P(z -
//     g)||_inf) of a bound that the gradient pushes against it are fixed for the CG solve and
//     moved onto that bound.
//  2. Steihaug-Toint CG on the free variables, from s = 0: minimize g.s + 1/2 s.H s with ||s|| <=
//     D; it stops at the forcing tolerance ||H s + g|| <= min(1e-4, sqrt(||g|| / ||g_0||)) ||g||
//     (superlinear convergence, Dembo-Eisenstat-Steihaug; the cap is far tighter than the usual
//     0.5 because an iteration costs far more than a product, see kMaxForcing), on the trust-region
//     boundary, along a direction of non-positive curvature to the boundary, after
//     kMaxCgIterations, or, with Gauss-Newton products, once the model has resolved the objective
//     (CgStop: its decrease over the last kModelWindow iterations is within
//     OptimizerOptions::cg_objective_resolution of the objective it predicts, and within
//     min(kMaxModelFraction, sqrt(||g|| / ||g_0||)) of its own decrease).
//  3. The step is projected onto the box: d = P(z + s) - z. The model's decrease is
//     pred = -(g.d + 1/2 d.H d), taken from CG when d = s and from one more product otherwise.
//  4. rho = (f(z) - f(z + d)) / pred. rho > 1e-4 accepts the step (the gradient is evaluated
//     there, the trial's value alone otherwise). rho < 1/4 sets D = ||d|| / 4; rho > 3/4 on the
//     boundary doubles D. A trial the functional cannot evaluate counts as rho = -inf.
// A rejected step shrinks D and takes the point of the same CG path at the new radius (the
// path's iterates are kept), so it needs no new products.
//
// Stops: converged when the projected gradient norm is <= gradient_tolerance (or by
// objective_tolerance / step_tolerance); when the trust region collapses to round-off, converged
// if the projected gradient is within 100x of the tolerance (as NLopt's ROUNDOFF_LIMITED
// verdict), failed otherwise. One history row per accepted step. A resumed run takes back the
// trust radius ("trust_region_radius").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "optimizers/backend_detail.hpp"
#include "optimizers/backend_registry.hpp"
#include "forward/core/format_number.hpp"

namespace tailor::detail {

namespace {

constexpr double kAccept = 1e-4;          // rho above which a step is taken
constexpr double kMaxActiveEpsilon = 1e-3;
constexpr int kMaxCgIterations = 200;     // per Newton iteration
// The forcing term's cap: CG solves to at most 1e-4 of the gradient. A product costs two
// back-solves, a Newton iteration a factorization and a forward and adjoint solve (on
// recovery_bench at 48k tets, one thread: about 0.08 s against 1 s), so loosely solved steps
// (the textbook cap is 0.5) cost more iterations than their CG saves, and truncated steps leave
// the stiff directions unbalanced, which the next iteration then pays a factorization to fix.
// Measured (one thread, shared machine), to recovery_bench's target: at 6k tets caps 1e-2 /
// 1e-3 / 1e-4 / 1e-5 took 24 / 18 / 6 / 6 factorizations and 255 / 218 / 170 / 260 products; at
// 48k, 1e-2 and 1e-4 took 24 and 7 factorizations, 315 and 283 products (59 s and 26 s). Whole
// runs of scenes/cantilever_handle.json took 145 / 157 / 54 / 59 factorizations and 729 / 940 /
// 741 / 2364 products.
constexpr double kMaxForcing = 1e-4;
constexpr double kRoundOffSlack = 100.0;  // on gradient_tolerance, when the radius collapses
// CG's model test (CgStop): the window, in CG iterations, whose decrease estimates what is left
// of the model's decrease, and the cap of the fraction of the step's own decrease that may be
// left (min(kMaxModelFraction, sqrt(||g|| / ||g_0||)): tighter as the gradient falls, as the
// residual forcing term, so that the outer iterations stay superlinear).
constexpr int kModelWindow = 5;
constexpr double kMaxModelFraction = 1e-2;

// Curvature products on the free variables: the product of v (zero on the fixed ones) with
// its fixed components zeroed.
enum class Source { hessian_vector, gauss_newton, gradient_difference };

std::string to_string(Source source) {
  switch (source) {
    case Source::hessian_vector:
      return "Hessian-vector products";
    case Source::gauss_newton:
      return "Gauss-Newton products";
    case Source::gradient_difference:
      return "products by gradient differences";
  }
  return "?";
}

class Curvature {
 public:
  Curvature(Tracker& tracker, Source source) : tracker_(tracker), source_(source) {}
  // Products at z (gradient g) on the variables not fixed, in the variables scaled by `scale`
  // (s_hat = scale (.) s: the products are scale^-1 (.) H (scale^-1 (.) v)); empty = unscaled.
  void at(const Vector& z, const Vector& g, const std::vector<char>& fixed, const Vector& scale) {
    z_ = z;
    g_ = g;
    fixed_ = fixed;
    scale_ = scale;
  }
  // False when the product could not be evaluated (the Tracker then may have requested a stop).
  bool apply(const Vector& v, Vector& out) {
    if (scale_.size() == 0) return apply_unscaled(v, out, true);
    const Vector unscaled = v.cwiseQuotient(scale_);
    if (!apply_unscaled(unscaled, out, true)) return false;
    out = out.cwiseQuotient(scale_);
    return true;
  }
  // H v in the natural variables; with free_only, on the variables not fixed.
  bool apply_unscaled(const Vector& v, Vector& out, bool free_only) {
    ++products_;
    const bool ok = source_ == Source::gradient_difference
                        ? tracker_.gradient_difference(z_, g_, v, out)
                        : tracker_.curvature_product(z_, v, source_ == Source::gauss_newton, out);
    if (!ok) return false;
    if (free_only)
      for (std::size_t i = 0; i < fixed_.size(); ++i)
        if (fixed_[i]) out[static_cast<Eigen::Index>(i)] = 0.0;
    return true;
  }
  int products() const { return products_; }

 private:
  Tracker& tracker_;
  Source source_;
  Vector z_, g_, scale_;
  std::vector<char> fixed_;
  int products_ = 0;
};

// The Steihaug-Toint path: the CG iterates s_0 = 0, s_1, ..., s_k inside the radius it was run
// with, and possibly an open last segment from s_k along `tail` (to the boundary: the radius was
// reached, or the curvature along tail is not positive). The model m(s) = g.s + 1/2 s.H s is
// quadratic along each segment, so the path's point at any smaller radius and its model value
// follow from scalars kept per segment: a rejected step is retried without new products. ||s||
// increases along the path (Steihaug's theorem), so the point at radius D is where the path
// first leaves the ball.
struct CgPath {
  std::vector<Vector> points;  // s_0 = 0, ..., s_k
  std::vector<double> model;   // m(s_j)
  // Segment j (from s_j to s_{j+1}, t in [0, 1]): m = model[j] + t slope[j] + t^2 / 2 curvature[j].
  std::vector<double> slope, curvature;
  bool has_tail = false;  // open segment from s_k along tail, t >= 0
  Vector tail;
  double tail_slope = 0.0, tail_curvature = 0.0;
  int iterations = 0;
  int model_stops = 0;  // 1 when CgStop's model test ended it
  std::string ending;
  bool failed = false;  // a product could not be evaluated

  // The path's point of norm min(radius, its end) and its model value.
  void point_at(double radius, Vector& s, double& m) const {
    const std::size_t k = points.size() - 1;
    for (std::size_t j = 0; j < k; ++j) {
      if (points[j + 1].norm() < radius) continue;
      const Vector d = points[j + 1] - points[j];
      const double t = to_boundary(points[j], d, radius);
      s = points[j] + t * d;
      m = model[j] + t * slope[j] + 0.5 * t * t * curvature[j];
      return;
    }
    if (has_tail) {
      const double t = to_boundary(points[k], tail, radius);
      s = points[k] + t * tail;
      m = model[k] + t * tail_slope + 0.5 * t * t * tail_curvature;
      return;
    }
    s = points[k];
    m = model[k];
  }

  // t >= 0 with ||s + t d|| = radius (||s|| <= radius).
  static double to_boundary(const Vector& s, const Vector& d, double radius) {
    const double a = d.squaredNorm(), b = 2.0 * s.dot(d), c = s.squaredNorm() - radius * radius;
    if (a <= 0.0) return 0.0;
    const double root = std::sqrt(std::max(b * b - 4.0 * a * c, 0.0));
    // The positive root, without cancellation (c <= 0).
    return b > 0.0 ? (c < 0.0 ? -2.0 * c / (b + root) : 0.0) : (-b + root) / (2.0 * a);
  }
};

// When CG stops besides the trust-region boundary, non-positive curvature and the iteration cap.
//  residual  ||H s + g|| <= residual (the forcing term times ||g||).
//  model     with Gauss-Newton products the model f + m(s) = 1/2 ||r + J s||^2 is the objective
//            the step predicts, a sum of squares. CG's iterate j has m_j - m_* = 1/2 ||s_j -
//            s_*||_H^2, and the decrease over the last w iterations, m_{j-w} - m_j, estimates that
//            gap at j - w from below and bounds the gap at j from above wherever CG converges at a
//            useful rate (the Hestenes-Stiefel estimate with delay w: Strakos & Tichy, ETNA 13,
//            2002). Stop when it is at most `resolution` (f + m_j), the objective resolved to that
//            relative accuracy, and at most `fraction` |m_j|: the step then gets all but that
//            fraction of the model's decrease. The first test alone would stop at once wherever
//            f - f_* is already below resolution f (no progress to the gradient tolerance).
//            resolution 0 = off.
// A product costs two back-solves and an outer iteration a factorization (~30 products at 48k
// tets), so the residual test alone solves the last Newton steps far past what the objective
// shows: on recovery_bench 62 of the 170 products to the target at 6k tets, and 68 of 284 at 48k,
// went to the step that took the objective from 3.5% and 0.76% above its best to 1e-5 and 2e-8
// above it, where the bench asks for 1e-3 (docs/performance.md).
struct CgStop {
  double residual = 0.0;
  double objective = 0.0;  // f at z
  double resolution = 0.0;
  double fraction = 0.0;

  bool model_resolved(const std::vector<double>& model) const {
    const std::size_t j = model.size() - 1, w = static_cast<std::size_t>(kModelWindow);
    if (!(resolution > 0.0) || j < w) return false;
    const double m = model[j], decrease = model[j - w] - m;
    return decrease <= resolution * (objective + m) && decrease <= fraction * std::abs(m);
  }
};

// Steihaug-Toint CG for min g.s + 1/2 s.H s, ||s|| <= radius (g zero on the fixed variables).
CgPath steihaug(Curvature& H, Tracker& tracker, const Vector& g, double radius, const CgStop& stop) {
  CgPath path;
  const Eigen::Index n = g.size();
  Vector s = Vector::Zero(n), r = g, d = -g, Hd;
  double m = 0.0, rr = r.squaredNorm();
  path.points.push_back(s);
  path.model.push_back(0.0);
  if (std::sqrt(rr) <= stop.residual) {
    path.ending = "tolerance";
    return path;
  }
  for (int j = 0;; ++j) {
    if (j == kMaxCgIterations) {
      path.ending = "iteration cap";
      break;
    }
    if (!H.apply(d, Hd)) {
      path.failed = true;
      break;
    }
    ++path.iterations;
    if (tracker.stop_requested()) {
      path.failed = true;
      break;
    }
    const double dHd = d.dot(Hd), slope = r.dot(d);
    if (!(dHd > 0.0)) {  // not positive (or NaN): to the boundary along d
      path.has_tail = true;
      path.tail = d;
      path.tail_slope = slope;
      path.tail_curvature = std::isfinite(dHd) ? dHd : 0.0;
      path.ending = "negative curvature";
      break;
    }
    const double alpha = rr / dHd;
    if ((s + alpha * d).norm() >= radius) {
      path.has_tail = true;
      path.tail = d;
      path.tail_slope = slope;
      path.tail_curvature = dHd;
      path.ending = "trust-region boundary";
      break;
    }
    path.slope.push_back(alpha * slope);
    path.curvature.push_back(alpha * alpha * dHd);
    m += alpha * slope + 0.5 * alpha * alpha * dHd;
    s += alpha * d;
    r += alpha * Hd;
    path.points.push_back(s);
    path.model.push_back(m);
    const double rr_next = r.squaredNorm();
    if (std::sqrt(rr_next) <= stop.residual) {
      path.ending = "tolerance";
      break;
    }
    if (stop.model_resolved(path.model)) {
      path.ending = "model resolved";
      ++path.model_stops;
      break;
    }
    d = -r + (rr_next / rr) * d;
    rr = rr_next;
  }
  return path;
}

// The preconditioner's scaling at z (OptimizerOptions::precondition_curvature, off by default):
// scale = sqrt(D / mean(D)), D the functional's estimate of the Gauss-Newton diagonal
// (ReducedFunctional::gauss_newton_diagonal). CG in the scaled variables s_hat = scale (.) s is
// Jacobi-preconditioned CG and the trust region is the ellipsoid ||scale (.) s|| <= radius (the
// preconditioner's norm: Steihaug 1983; Conn, Gould & Toint, Trust-Region Methods, 2000, sec.
// 7.5). The mean normalization keeps the trust radius in the units of an unscaled RMS step.
// Measured on recovery_bench (docs/performance.md): 13% fewer products at 48k tets, 5% more at
// 6k, and even the exact diagonal costs more products on a small recovery: a per-element field
// seen through an elliptic solve has its curvature spread between smooth and rough fields, which
// no diagonal removes.
bool diagonal_scale(Tracker& tracker, const Vector& z, Vector& scale) {
  Vector diagonal;
  if (!tracker.gauss_newton_diagonal(z, diagonal)) return false;
  scale = (diagonal / diagonal.mean()).cwiseSqrt();
  return true;
}

bool choose_curvature(Tracker& tracker, Source& source, std::string& why_not) {
  const ReducedFunctional& f = tracker.functional();
  const bool exact = f.has_hessian_vector(), gn = f.has_gauss_newton_vector();
  switch (tracker.options().curvature) {
    case CurvatureProducts::exact:
      source = Source::hessian_vector;
      if (!exact)
        why_not =
            "curvature 'exact' asks for Hessian-vector products, which this functional has not (an objective "
            "term without second derivatives)";
      return exact;
    case CurvatureProducts::gauss_newton:
      source = Source::gauss_newton;
      if (!gn)
        why_not =
            "curvature 'gauss_newton' asks for Gauss-Newton products, which this functional has not (its "
            "objective is not least squares)";
      return gn;
    case CurvatureProducts::automatic:
      break;
  }
  // Gauss-Newton where the objective is least squares: its products need no third derivatives
  // (about a fifth of an exact product's cost on recovery_bench) and it is positive
  // semidefinite (the exact Hessian of a misfit far from its minimum is not, and CG then stops
  // at the trust-region boundary); at a zero-residual minimum it is the Hessian. Without either,
  // gradient differences: each product then costs a forward and an adjoint solve.
  source = gn ? Source::gauss_newton : exact ? Source::hessian_vector : Source::gradient_difference;
  return true;
}

}  // namespace

BackendOutcome run_newton_cg(Tracker& tracker, const Vector& z0) {
  if (!tracker.constraints().empty())
    return {OptimizerStatus::failed, "newton_cg supports bounds only, not general constraints", std::nullopt};
  Source source = Source::hessian_vector;
  std::string why_not;
  if (!choose_curvature(tracker, source, why_not)) return {OptimizerStatus::failed, why_not, std::nullopt};
  const std::string products = to_string(source);
  const OptimizerOptions& options = tracker.options();
  const Eigen::Index n = tracker.size();
  const Vector& lower = tracker.lower();
  const Vector& upper = tracker.upper();

  Vector z = z0, g;
  double f = tracker.value_and_gradient(z, g);
  if (!std::isfinite(f))
    return {OptimizerStatus::failed, "the objective cannot be evaluated at the starting point", std::nullopt};
  tracker.record_iteration(z, f);  // resuming: the checkpoint's row, not written again
  const double g0 = std::max(g.norm(), std::numeric_limits<double>::min());
  // An RMS change of 1 per variable at first (z in natural units, such as log E); then adapted.
  double radius = tracker.resumed_state("trust_region_radius").value_or(std::sqrt(static_cast<double>(n)));
  Curvature H(tracker, source);
  bool precondition = options.precondition_curvature;
  int cg_iterations = 0, rejected = 0, model_stops = 0;
  const auto summary = [&] {
    return " (" + std::to_string(tracker.iterations()) + " steps, " + std::to_string(rejected) + " rejected, " +
           std::to_string(cg_iterations) + " CG iterations, " +
           (model_stops ? std::to_string(model_stops) + " CG solves stopped with the objective resolved, " : "") +
           std::to_string(H.products()) + " " + products +
           (precondition ? ", preconditioned by the Gauss-Newton diagonal" : "") + ")";
  };
  const auto round_off_verdict = [&](double gradient_norm, const std::string& what) -> BackendOutcome {
    if (gradient_norm <= kRoundOffSlack * options.gradient_tolerance)
      return {OptimizerStatus::converged,
              what + " at projected gradient norm " + format_scientific(gradient_norm) + " (within " +
                  format_scientific(kRoundOffSlack) + " x gradient_tolerance)" + summary(),
              z};
    return {OptimizerStatus::failed,
            what + " at projected gradient norm " + format_scientific(gradient_norm) + " > " + format_scientific(kRoundOffSlack) +
                " x gradient_tolerance" + summary(),
            z};
  };

  std::vector<char> fixed(static_cast<std::size_t>(n));
  for (;;) {
    const double gradient_norm = tracker.projected_gradient_norm(z, g);
    if (gradient_norm <= options.gradient_tolerance)
      return {OptimizerStatus::converged,
              "projected gradient norm " + format_scientific(gradient_norm) + " <= gradient_tolerance" + summary(), z};
    if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
    if (tracker.iterations() >= options.max_iterations)
      return {OptimizerStatus::max_iterations,
              "reached max_iterations = " + std::to_string(options.max_iterations) + summary(), z};

    // 1. The epsilon-active set; its variables go onto their bounds.
    const double eps = std::min(kMaxActiveEpsilon, gradient_norm);
    Vector g_free = g, to_bound = Vector::Zero(n);
    bool moves_fixed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const bool at_lower = z[i] <= lower[i] + eps && g[i] > 0.0;
      const bool at_upper = z[i] >= upper[i] - eps && g[i] < 0.0;
      fixed[static_cast<std::size_t>(i)] = at_lower || at_upper;
      if (!(at_lower || at_upper)) continue;
      g_free[i] = 0.0;
      to_bound[i] = (at_lower ? lower[i] : upper[i]) - z[i];
      moves_fixed = moves_fixed || to_bound[i] != 0.0;
    }

    // 2. CG on the free variables, in the variables scaled by the preconditioner.
    Vector scale;
    if (precondition && !diagonal_scale(tracker, z, scale)) {
      if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
      precondition = false;  // the functional has no estimate here: plain CG from now on
    }
    H.at(z, g, fixed, scale);
    const Vector g_hat = scale.size() ? Vector(g_free.cwiseQuotient(scale)) : g_free;
    const double g_norm = g_free.norm();
    const double decay = std::sqrt(g_norm / g0);
    CgStop stop;
    stop.residual = std::min(kMaxForcing, decay) * g_hat.norm();
    if (source == Source::gauss_newton) {
      stop.objective = f;
      stop.resolution = options.cg_objective_resolution;
      stop.fraction = std::min(kMaxModelFraction, decay);
    }
    const CgPath path = steihaug(H, tracker, g_hat, radius, stop);
    cg_iterations += path.iterations;
    model_stops += path.model_stops;
    if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
    if (path.failed)
      return {OptimizerStatus::failed, "a curvature product could not be evaluated" + summary(), z};

    // 3-4. Trial steps along the path, shrinking the radius until one is taken.
    double step_radius = radius;
    for (;;) {
      Vector s;
      double model = 0.0;
      path.point_at(step_radius, s, model);
      const bool on_boundary = s.norm() >= 0.99 * step_radius;
      if (scale.size()) s = s.cwiseQuotient(scale);
      s += to_bound;
      const Vector unprojected = z + s;
      const Vector trial = tracker.project(unprojected);
      const Vector d = trial - z;
      double predicted = -model;
      if (moves_fixed || trial != unprojected) {
        // The projection (or a move onto a bound) changed the step: the model at d itself.
        Vector Hd;
        if (!H.apply_unscaled(d, Hd, false))
          return tracker.stop_requested()
                     ? BackendOutcome{OptimizerStatus::failed, "", z}
                     : BackendOutcome{OptimizerStatus::failed,
                                      "a curvature product could not be evaluated" + summary(), z};
        predicted = -(g.dot(d) + 0.5 * d.dot(Hd));
      }
      const double d_norm = d.norm();
      const double d_radius = scale.size() ? d.cwiseProduct(scale).norm() : d_norm;  // the trust-region norm
      const bool collapsed = d_norm <= std::numeric_limits<double>::epsilon() * (1.0 + z.norm());
      if (collapsed) return round_off_verdict(gradient_norm, "the trust region collapsed");
      double rho = -std::numeric_limits<double>::infinity();
      Vector g_trial;
      double f_trial = std::numeric_limits<double>::infinity();
      if (predicted > 0.0) {
        f_trial = tracker.value(trial);  // value only: a rejected trial needs no adjoint
        if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
        if (std::isfinite(f_trial)) rho = (f - f_trial) / predicted;
        // The model predicts less than the objective's round-off: the step cannot be judged.
        if (predicted <= 4.0 * std::numeric_limits<double>::epsilon() * std::abs(f) && !(f_trial < f))
          return round_off_verdict(gradient_norm, "the predicted decrease reached round-off");
      }
      if (rho > kAccept) {
        f_trial = tracker.value_and_gradient(trial, g_trial);
        if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
      }
      if (rho > kAccept && std::isfinite(f_trial)) {
        if (rho < 0.25)
          radius = 0.25 * d_radius;
        else if (rho > 0.75 && on_boundary)
          radius = std::max(radius, 2.0 * d_radius);
        z = trial;
        g = std::move(g_trial);
        f = f_trial;
        break;
      }
      ++rejected;
      step_radius = 0.25 * std::min(step_radius, d_radius);
      radius = step_radius;
    }
    tracker.set_backend_state("trust_region_radius", radius);
    tracker.record_iteration(z, f);
    tracker.apply_change_tests();
    if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
  }
}

}  // namespace tailor::detail

namespace tailor {

// The registry's entry (optimizers/backend_registry.hpp). It always uses curvature products;
// OptimizerOptions::exact_hessian (Ipopt's switch) does not apply.
BackendEntry newton_cg_backend_entry() {
  return {"newton_cg",
          "trust-region Newton-CG (Steihaug-Toint) on Hessian-vector or Gauss-Newton products, bounds",
          {.bounds = true},
          &detail::run_newton_cg};
}

}  // namespace tailor
