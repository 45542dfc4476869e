#include "forward/dynamics/example_damping.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor {

struct ExampleDamping::Scales {
  Vector gamma, kappa, dkappa;           // kappa = 2 gamma / (1 + gamma), dkappa = d kappa / d gamma
  std::vector<Vector> control_gradient;  // d gamma_i / d(controls of example i)
};

ExampleDamping::ExampleDamping(std::unique_ptr<RayleighDamping> base, const SparseMatrix& mass,
                               Matrix examples, Vector frequencies, Vector rest,
                               std::vector<DampingCurve> curves, int curve_offset, double amplitude_smoothing)
    : base_(std::move(base)),
      examples_(std::move(examples)),
      frequencies_(std::move(frequencies)),
      rest_(std::move(rest)),
      curve_offset_(curve_offset),
      smoothing_(amplitude_smoothing) {
  if (!base_) throw std::invalid_argument("ExampleDamping: no base Rayleigh damping");
  const Eigen::Index n = rest_.size(), r = examples_.cols();
  if (examples_.rows() != n || mass.rows() != n)
    throw std::invalid_argument("ExampleDamping: examples, mass and rest positions must have " +
                                std::to_string(n) + " rows");
  if (frequencies_.size() != r || static_cast<Eigen::Index>(curves.size()) != r)
    throw std::invalid_argument("ExampleDamping: one frequency and one curve per example are needed");
  if (!(smoothing_ >= 0.0))
    throw std::invalid_argument("ExampleDamping: the amplitude smoothing must be >= 0");
  mass_examples_ = mass * examples_;
  const Matrix gram = examples_.transpose() * mass_examples_;
  if ((gram - Matrix::Identity(r, r)).cwiseAbs().maxCoeff() > 1e-6)
    throw std::invalid_argument("ExampleDamping: examples are not M-orthonormal (use mass_orthonormalize)");
  amplitude_scale_.resize(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    if (!(frequencies_[i] > 0.0))
      throw std::invalid_argument("ExampleDamping: example " + std::to_string(i) +
                                  " has a non-positive frequency");
    amplitude_scale_[i] = examples_.col(i).cwiseAbs().maxCoeff();
    curve_begin_.push_back(num_controls_);
    curves_.emplace_back(curves[static_cast<std::size_t>(i)].knots);
    num_controls_ += curves_.back().size();
  }
  chi_ = Vector::Zero(r);
}

void ExampleDamping::set_amplitudes(Vector chi) {
  if (chi.size() != num_examples())
    throw std::invalid_argument("ExampleDamping: one amplitude per example is needed");
  chi_ = std::move(chi);
  x_start_.resize(0);
  v_start_.resize(0);
}

double ExampleDamping::amplitude(int i, const Vector& x, const Vector& v, Vector* gradient_x,
                                 Vector* gradient_v) const {
  const auto w = mass_examples_.col(i);
  const double a = amplitude_scale_[i], omega = frequencies_[i];
  const double q = w.dot(x - rest_), qd = w.dot(v);
  const double rho = std::sqrt(a * a * (q * q + qd * qd / (omega * omega)) + smoothing_ * smoothing_);
  // d chi / dq = a^2 q / rho, d chi / dqd = a^2 qd / (omega^2 rho); zero at rest when eps = 0.
  const double inv = rho > 0.0 ? 1.0 / rho : 0.0;
  if (gradient_x) *gradient_x = (a * a * q * inv) * w;
  if (gradient_v) *gradient_v = (a * a * qd * inv / (omega * omega)) * w;
  return rho - smoothing_;
}

void ExampleDamping::set_step_start(const Vector& x, const Vector& v) {
  for (int i = 0; i < num_examples(); ++i) chi_[i] = amplitude(i, x, v);
  x_start_ = x;
  v_start_ = v;
}

void ExampleDamping::add_step_start_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                                    Vector& x_start_bar, Vector& v_start_bar) const {
  if (x_start_.size() == 0) return;  // amplitudes set directly: no state dependence
  const Scales s = scales(p);
  const Vector mixed = scale_mixed(s, velocity(x), p, w);
  for (int i = 0; i < num_examples(); ++i) {
    double slope = 0.0;
    scale(i, p, &slope);
    if (slope == 0.0 || mixed[i] == 0.0) continue;
    Vector gx, gv;
    amplitude(i, x_start_, v_start_, &gx, &gv);
    x_start_bar += (mixed[i] * slope) * gx;
    v_start_bar += (mixed[i] * slope) * gv;
  }
}

double ExampleDamping::curve(int i, const Vector& p, double chi) const {
  return curves_[static_cast<std::size_t>(i)].evaluate(
      p.segment(curve_offset_ + curve_begin_[i], curves_[static_cast<std::size_t>(i)].size()), chi);
}

double ExampleDamping::scale(int i, const Vector& p, double* slope, Vector* control_gradient) const {
  const MonotoneCubic& c = curves_[static_cast<std::size_t>(i)];
  return c.evaluate(p.segment(curve_offset_ + curve_begin_[i], c.size()), chi_[i], slope, control_gradient);
}

ExampleDamping::Scales ExampleDamping::scales(const Vector& p) const {
  const int r = num_examples();
  Scales s;
  s.gamma.resize(r), s.kappa.resize(r), s.dkappa.resize(r);
  s.control_gradient.resize(static_cast<std::size_t>(r));
  for (int i = 0; i < r; ++i) {
    const double g = scale(i, p, nullptr, &s.control_gradient[static_cast<std::size_t>(i)]);
    if (!(g >= 0.0))
      throw std::invalid_argument("ExampleDamping: the damping scale of example " + std::to_string(i) +
                                  " is " + std::to_string(g) + " (control values must be >= 0)");
    s.gamma[i] = g;
    s.kappa[i] = 2.0 * g / (1.0 + g);
    s.dkappa[i] = 2.0 / ((1.0 + g) * (1.0 + g));
  }
  return s;
}

Vector ExampleDamping::transform(const Scales& s, const Vector& v) const {
  const Vector qd = mass_examples_.transpose() * v;
  return v + examples_ * ((s.kappa.array() - 1.0) * qd.array()).matrix();
}

namespace {

double rayleigh_value(const RayleighDamping& base, const Vector& v, const Vector& p) {
  double value = 0.0;
  EnergyRequest request;
  request.value = &value;
  base.evaluate_dissipation(v, p, request);
  return value;
}

Vector rayleigh_gradient(const RayleighDamping& base, const Vector& v, const Vector& p) {
  Vector g = Vector::Zero(v.size());
  EnergyRequest request;
  request.gradient = &g;
  base.evaluate_dissipation(v, p, request);
  return g;
}

}  // namespace

void ExampleDamping::evaluate_dissipation(const Vector& v, const Vector& p,
                                          const EnergyRequest& request) const {
  const int r = num_examples();
  if (request.hessian_values) {  // C on Rayleigh's pattern; the rest is low-rank
    EnergyRequest h;
    h.hessian_values = request.hessian_values;
    base_->evaluate_dissipation(v, p, h);
  }
  if (!request.value && !request.gradient) return;
  const Scales s = scales(p);
  const Vector qd = mass_examples_.transpose() * v;
  const Vector Tv = transform(s, v);
  Vector diagonal(r);  // (gamma_i - kappa_i^2) D_R(u_i)
  for (int i = 0; i < r; ++i)
    diagonal[i] = (s.gamma[i] - s.kappa[i] * s.kappa[i]) * rayleigh_value(*base_, examples_.col(i), p);
  if (request.value) *request.value += rayleigh_value(*base_, Tv, p) + diagonal.dot(qd.cwiseProduct(qd));
  if (request.gradient) {
    const Vector g = rayleigh_gradient(*base_, Tv, p);
    const Vector Ug = examples_.transpose() * g;
    // T^T g + sum_i 2 (gamma_i - kappa_i^2) D_R(u_i) qd_i w_i
    *request.gradient +=
        g + mass_examples_ *
                ((s.kappa.array() - 1.0) * Ug.array() + 2.0 * diagonal.array() * qd.array()).matrix();
  }
}

void ExampleDamping::add_dissipation_low_rank_hessian(const Vector& v, const Vector& p,
                                                      LowRankHessian& update) const {
  (void)v;
  const int r = num_examples();
  if (r == 0) return;
  const Scales s = scales(p);
  Matrix Z(examples_.rows(), r);  // C U
  for (int i = 0; i < r; ++i) Z.col(i) = rayleigh_gradient(*base_, examples_.col(i), p);
  const Matrix A = examples_.transpose() * Z;
  const Vector e = s.kappa.array() - 1.0;
  Matrix F(examples_.rows(), 2 * r);
  F << mass_examples_, Z;
  Matrix G = Matrix::Zero(2 * r, 2 * r);
  G.topLeftCorner(r, r) = e.asDiagonal() * A * e.asDiagonal();
  for (int i = 0; i < r; ++i) {
    G(i, i) += (s.gamma[i] - s.kappa[i] * s.kappa[i]) * A(i, i);
    G(i, r + i) = G(r + i, i) = e[i];
  }
  update.append(F, G);
}

void ExampleDamping::add_dissipation_param_gradient(const Vector& v, const Vector& p,
                                                    Vector& gradient_p) const {
  const int r = num_examples();
  const Scales s = scales(p);
  const Vector qd = mass_examples_.transpose() * v;
  const Vector Tv = transform(s, v);
  base_->add_dissipation_param_gradient(Tv, p, gradient_p);
  const Vector g = rayleigh_gradient(*base_, Tv, p);
  for (int i = 0; i < r; ++i) {
    const auto u = examples_.col(i);
    const double excess = s.gamma[i] - s.kappa[i] * s.kappa[i];
    Vector du = Vector::Zero(p.size());  // d D_R(u_i) / dp
    base_->add_dissipation_param_gradient(u, p, du);
    gradient_p += (excess * qd[i] * qd[i]) * du;
    // dD / dgamma_i = kappa_i' qd_i u_i^T g_R(T v) + (1 - 2 kappa_i kappa_i') D_R(u_i) qd_i^2
    const double dD = s.dkappa[i] * qd[i] * u.dot(g) +
                      (1.0 - 2.0 * s.kappa[i] * s.dkappa[i]) * rayleigh_value(*base_, u, p) * qd[i] * qd[i];
    const Vector& dg = s.control_gradient[static_cast<std::size_t>(i)];
    gradient_p.segment(curve_offset_ + curve_begin_[i], dg.size()) += dD * dg;
  }
}

Vector ExampleDamping::scale_mixed(const Scales& s, const Vector& v, const Vector& p, const Vector& w) const {
  const int r = num_examples();
  const Vector qd = mass_examples_.transpose() * v, qw = mass_examples_.transpose() * w;
  const Vector Tv = transform(s, v), Tw = transform(s, w);
  Vector out(r);
  for (int i = 0; i < r; ++i) {
    const auto u = examples_.col(i);
    const Vector z = rayleigh_gradient(*base_, u, p);  // C u_i
    // d/dgamma_i of (T w)^T C (T v) + sum_i 2 (gamma_i - kappa_i^2) D_R(u_i) qd_i (w_i^T w)
    out[i] = s.dkappa[i] * (qw[i] * z.dot(Tv) + qd[i] * z.dot(Tw)) +
             2.0 * (1.0 - 2.0 * s.kappa[i] * s.dkappa[i]) * rayleigh_value(*base_, u, p) * qd[i] * qw[i];
  }
  return out;
}

void ExampleDamping::add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                                           Vector& gradient_p) const {
  const int r = num_examples();
  const Scales s = scales(p);
  const Vector qd = mass_examples_.transpose() * v, qw = mass_examples_.transpose() * w;
  // w^T dD/dv = (T w)^T g_R(T v) + sum_i 2 (gamma_i - kappa_i^2) D_R(u_i) qd_i (w_i^T w)
  base_->add_dissipation_mixed_transpose_times(transform(s, v), p, transform(s, w), gradient_p);
  const Vector d_gamma = scale_mixed(s, v, p, w);
  for (int i = 0; i < r; ++i) {
    const double excess = s.gamma[i] - s.kappa[i] * s.kappa[i];
    Vector du = Vector::Zero(p.size());
    base_->add_dissipation_param_gradient(examples_.col(i), p, du);
    gradient_p += (2.0 * excess * qd[i] * qw[i]) * du;
    const Vector& dg = s.control_gradient[static_cast<std::size_t>(i)];
    gradient_p.segment(curve_offset_ + curve_begin_[i], dg.size()) += d_gamma[i] * dg;
  }
}

}  // namespace tailor
