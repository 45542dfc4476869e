// The curvature barrier of the macro-scale sheet on fitted bending limits (see
// macro_bending_limit.hpp).
#include "forward/interlocking/macro_bending_limit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "forward/core/dual2.hpp"
#include "forward/core/psd_projection.hpp"
#include "forward/interlocking/macro_boundary_fit.hpp"

namespace tailor::interlocking {
namespace {

constexpr double kHingeInfinity = std::numeric_limits<double>::infinity();

// n1 . n2 / (|n1| |n2|) of a hinge's two triangles from its 4 vertices' 12 coordinates X (corner c
// of triangle t is vertex tri[t][c]; normals (x_b - x_a) x (x_c - x_a)).
template <class Scalar>
Scalar hinge_cosine(const Scalar* X, const int (&tri)[2][3]) {
  Scalar n[2][3];
  for (int t = 0; t < 2; ++t) {
    Scalar e1[3], e2[3];
    for (int d = 0; d < 3; ++d) {
      e1[d] = X[3 * tri[t][1] + d] - X[3 * tri[t][0] + d];
      e2[d] = X[3 * tri[t][2] + d] - X[3 * tri[t][0] + d];
    }
    n[t][0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[t][1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[t][2] = e1[0] * e2[1] - e1[1] * e2[0];
  }
  const Scalar n12 = n[0][0] * n[1][0] + n[0][1] * n[1][1] + n[0][2] * n[1][2];
  const Scalar n11 = n[0][0] * n[0][0] + n[0][1] * n[0][1] + n[0][2] * n[0][2];
  const Scalar n22 = n[1][0] * n[1][0] + n[1][1] * n[1][1] + n[1][2] * n[1][2];
  return n12 / sqrt(n11 * n22);
}

// The basis row of the Fourier fit at theta: 1, cos 2 theta, sin 2 theta, ..., cos 2K theta, sin 2K theta.
void fourier_row(double theta, int order, double* row) {
  row[0] = 1.0;
  for (int k = 1; k <= order; ++k) {
    row[2 * k - 1] = std::cos(2.0 * k * theta);
    row[2 * k] = std::sin(2.0 * k * theta);
  }
}

}  // namespace

double BendingLimitFit::compliance(double theta) const {
  const int order = static_cast<int>(coefficients.size() - 1) / 2;
  double c = coefficients[0];
  for (int k = 1; k <= order; ++k)
    c += coefficients[static_cast<std::size_t>(2 * k - 1)] * std::cos(2.0 * k * theta) +
         coefficients[static_cast<std::size_t>(2 * k)] * std::sin(2.0 * k * theta);
  return c;
}

double BendingLimitFit::limit(double theta) const { return 1.0 / compliance(theta); }

BendingLimitFit fit_bending_limits(const std::vector<Eigen::Vector2d>& samples, int order) {
  if (order < 0) throw std::invalid_argument("fit_bending_limits: the order must be >= 0");
  const int m = static_cast<int>(samples.size()), n = 2 * order + 1;
  Eigen::MatrixXd design(m, n);
  Eigen::VectorXd kappa(m);
  std::vector<double> distinct, row(static_cast<std::size_t>(n));
  for (int i = 0; i < m; ++i) {
    const Eigen::Vector2d& s = samples[static_cast<std::size_t>(i)];
    if (!s.allFinite() || !(s.y() > 0.0))
      throw std::invalid_argument("fit_bending_limits: sample " + std::to_string(i) +
                                  " needs a finite angle and a positive curvature");
    fourier_row(s.x(), order, row.data());
    for (int k = 0; k < n; ++k) design(i, k) = row[static_cast<std::size_t>(k)];
    kappa[i] = 1.0 / s.y();  // the series is fitted to 1 / kappa (see the header)
    const double t = s.x() - M_PI * std::floor(s.x() / M_PI);  // theta mod pi
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&](double d) { return std::min(std::abs(d - t), M_PI - std::abs(d - t)) < 1e-9; }))
      distinct.push_back(t);
  }
  if (static_cast<int>(distinct.size()) < n)
    throw std::invalid_argument("fit_bending_limits: " + std::to_string(distinct.size()) +
                                " distinct directions (mod 180 degrees) cannot fix order " + std::to_string(order));
  BendingLimitFit fit;
  fit.coefficients = least_squares(design, kappa);
  fit.samples = m;
  double squares = 0.0;
  for (int i = 0; i < m; ++i) {
    const Eigen::Vector2d& sample = samples[static_cast<std::size_t>(i)];
    const double c = fit.compliance(sample.x());
    const double residual = c > 0.0 ? std::abs(1.0 / c - sample.y()) : kHingeInfinity;
    squares += residual * residual;
    fit.max_residual = std::max(fit.max_residual, residual);
  }
  fit.rms_residual = std::sqrt(squares / m);
  double min_compliance = fit.compliance(0.0), max_compliance = min_compliance;
  for (int k = 1; k < 720; ++k) {
    min_compliance = std::min(min_compliance, fit.compliance(M_PI * k / 720));
    max_compliance = std::max(max_compliance, fit.compliance(M_PI * k / 720));
  }
  if (!(min_compliance > 0.0))
    throw std::invalid_argument("fit_bending_limits: the fitted 1 / kappa is not positive everywhere (lower the order)");
  fit.min_limit = 1.0 / max_compliance;
  return fit;
}

BendingLimitTerm::BendingLimitTerm(const Mesh& flat, const BendingLimitFit& fit, CurvatureBarrier barrier)
    : barrier_(barrier) {
  if (flat.dim() != 2 || flat.elements.cols() != 3)
    throw std::invalid_argument("BendingLimitTerm: the rest sheet must be a 2D triangle mesh");
  if (fit.coefficients.empty() || !(barrier.stiffness > 0.0) ||
      !(barrier.activation > 0.0 && barrier.activation < 1.0))
    throw std::invalid_argument("BendingLimitTerm: needs a fit, stiffness > 0 and 0 < activation < 1");
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int k = 0; k < flat.num_elements(); ++k)
    for (int a = 0; a < 3; ++a) {
      const int i = flat.elements(k, a), j = flat.elements(k, (a + 1) % 3);
      edge_faces[{std::min(i, j), std::max(i, j)}].push_back(k);
    }
  const auto rest = [&](int v) -> Eigen::Vector2d { return flat.rest_positions.row(v).transpose(); };
  const auto area = [&](int k) {
    const Eigen::Vector2d e1 = rest(flat.elements(k, 1)) - rest(flat.elements(k, 0));
    const Eigen::Vector2d e2 = rest(flat.elements(k, 2)) - rest(flat.elements(k, 0));
    return 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
  };
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 2) continue;  // boundary edges carry no hinge
    Hinge h;
    h.vertices[0] = edge.first;
    h.vertices[1] = edge.second;
    for (int t = 0; t < 2; ++t) {
      const int k = faces[static_cast<std::size_t>(t)];
      for (int c = 0; c < 3; ++c) {
        const int v = flat.elements(k, c);
        if (v != edge.first && v != edge.second) h.vertices[2 + t] = v;
      }
    }
    for (int t = 0; t < 2; ++t)
      for (int c = 0; c < 3; ++c) {
        const int v = flat.elements(faces[static_cast<std::size_t>(t)], c);
        h.triangles[t][c] = static_cast<int>(std::find(h.vertices, h.vertices + 4, v) - h.vertices);
      }
    const Eigen::Vector2d e = rest(edge.second) - rest(edge.first);
    const double a1 = area(faces[0]), a2 = area(faces[1]);
    h.length = (a1 + a2) / e.norm();
    h.weight = (a1 + a2) / 3.0;
    h.angle = std::atan2(e.x(), -e.y());  // the in-plane normal (-e_y, e_x) up to sign (kappa has period pi)
    h.limit = fit.limit(h.angle);
    hinges_.push_back(h);
  }
}

double BendingLimitTerm::margin(const Vector& x, const Hinge& h) const {
  double X[12];
  for (int a = 0; a < 4; ++a)
    for (int d = 0; d < 3; ++d) X[3 * a + d] = x[3 * h.vertices[a] + d];
  const double c = hinge_cosine(X, h.triangles);
  if (!std::isfinite(c)) return -kHingeInfinity;  // a degenerate triangle
  return 1.0 - 2.0 * (1.0 - c) / (h.length * h.length * h.limit * h.limit);
}

void BendingLimitTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  const double gh = barrier_.activation;
  for (std::size_t k = 0; k < hinges_.size(); ++k) {
    const Hinge& h = hinges_[k];
    double* slots = request.hessian_values ? request.hessian_values + 144 * k : nullptr;
    if (slots) std::fill(slots, slots + 144, 0.0);
    const double g = margin(x, h);
    if (!(g > 0.0)) {
      if (request.value) *request.value = kHingeInfinity;
      continue;
    }
    if (g >= gh) continue;
    const double scale = barrier_.stiffness * h.weight;
    if (!request.gradient && !slots) {
      if (request.value) *request.value -= scale * (g - gh) * (g - gh) * std::log(g / gh);
      continue;
    }
    using D = Dual2<12>;
    D X[12];
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d) X[3 * a + d] = D::variable(x[3 * h.vertices[a] + d], 3 * a + d);
    const D gd = 1.0 - 2.0 * (1.0 - hinge_cosine(X, h.triangles)) / (h.length * h.length * h.limit * h.limit);
    const D e = -scale * (gd - gh) * (gd - gh) * log(gd / gh);
    if (request.value) *request.value += e.v;
    if (request.gradient)
      for (int a = 0; a < 4; ++a)
        for (int d = 0; d < 3; ++d) (*request.gradient)[3 * h.vertices[a] + d] += e.g[3 * a + d];
    if (slots) {
      Eigen::Matrix<double, 12, 12> H = e.h;
      if (request.hessian_mode == HessianMode::projected) project_psd(H);
      for (int r = 0; r < 12; ++r)
        for (int c = 0; c < 12; ++c) slots[12 * r + c] = H(r, c);
    }
  }
}

void BendingLimitTerm::hessian_pattern(HessianPattern& pattern) const {
  for (const Hinge& h : hinges_)
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c)
        pattern.push_back({3 * h.vertices[r / 3] + r % 3, 3 * h.vertices[c / 3] + c % 3});
}

double BendingLimitTerm::max_step(const Vector& x, const Vector& dx) const {
  constexpr int kSamples = 16;
  double t_max = 1.0;
  for (const Hinge& h : hinges_) {
    const double g0 = margin(x, h);
    if (!(g0 > 0.0)) return 0.0;
    const double floor = 0.2 * g0;
    // The hinge's 12 coordinates along the step.
    double X0[12], DX[12];
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d) {
        X0[3 * a + d] = x[3 * h.vertices[a] + d];
        DX[3 * a + d] = dx[3 * h.vertices[a] + d];
      }
    const auto below_local = [&](double t) {
      double X[12];
      for (int i = 0; i < 12; ++i) X[i] = X0[i] + t * DX[i];
      const double c = hinge_cosine(X, h.triangles);
      const double g = std::isfinite(c) ? 1.0 - 2.0 * (1.0 - c) / (h.length * h.length * h.limit * h.limit) : -1.0;
      return !(g > floor);
    };
    double t_ok = 0.0;
    for (int i = 1; i <= kSamples; ++i) {
      const double t = t_max * i / kSamples;
      if (!below_local(t)) {
        t_ok = t;
        continue;
      }
      double lo = t_ok, hi = t;
      for (int it = 0; it < 30; ++it) {
        const double mid = 0.5 * (lo + hi);
        (below_local(mid) ? hi : lo) = mid;
      }
      t_max = lo;
      break;
    }
  }
  return t_max;
}

Eigen::VectorXd BendingLimitTerm::curvatures(const Vector& x) const {
  Eigen::VectorXd kappa(num_hinges());
  for (int k = 0; k < num_hinges(); ++k) {
    const Hinge& h = hinges_[static_cast<std::size_t>(k)];
    const double g = margin(x, h);
    kappa[k] = h.limit * std::sqrt(std::max(0.0, 1.0 - g));
  }
  return kappa;
}

Eigen::VectorXd BendingLimitTerm::margins(const Vector& x) const {
  Eigen::VectorXd g(num_hinges());
  for (int k = 0; k < num_hinges(); ++k) g[k] = margin(x, hinges_[static_cast<std::size_t>(k)]);
  return g;
}

Eigen::VectorXd BendingLimitTerm::normal_angles() const {
  Eigen::VectorXd a(num_hinges());
  for (int k = 0; k < num_hinges(); ++k) a[k] = hinges_[static_cast<std::size_t>(k)].angle;
  return a;
}

Eigen::VectorXd BendingLimitTerm::limits() const {
  Eigen::VectorXd a(num_hinges());
  for (int k = 0; k < num_hinges(); ++k) a[k] = hinges_[static_cast<std::size_t>(k)].limit;
  return a;
}

}  // namespace tailor::interlocking
