// The cylinder's periodicity map and the reduced contact energy through it (see
// curved_periodicity.hpp).
#include "forward/interlocking/curved_periodicity.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

#include "forward/interlocking/cell_equilibrium.hpp"
#include "forward/rigid/rotation.hpp"

namespace tailor::interlocking {
namespace {

// h1 = sin(p) / p and h2 = (1 - cos(p)) / p with first derivatives: the circle through the origin
// of curvature kappa reaches (sin(kappa u), 1 - cos(kappa u)) / kappa = u (h1, h2)(kappa u) at arc
// length u. Taylor series below |p| = 0.1 (truncation below 1e-16), closed forms beyond.
struct ArcCoefficients {
  double h1, dh1, h2, dh2;
};
ArcCoefficients arc_coefficients(double p) {
  const double q = p * p;
  if (std::abs(p) < 0.1)
    return {1.0 - q / 6.0 * (1.0 - q / 20.0 * (1.0 - q / 42.0 * (1.0 - q / 72.0))),
            -p / 3.0 * (1.0 - q / 10.0 * (1.0 - q / 28.0 * (1.0 - q / 54.0))),
            p / 2.0 * (1.0 - q / 12.0 * (1.0 - q / 30.0 * (1.0 - q / 56.0 * (1.0 - q / 90.0)))),
            0.5 - q / 8.0 * (1.0 - q / 18.0 * (1.0 - q / 40.0))};
  const double s = std::sin(p), c = std::cos(p);
  return {s / p, (p * c - s) / q, (1.0 - c) / p, (p * s - (1.0 - c)) / q};
}

Eigen::Vector3d plane_vector(const Eigen::Vector2d& v) { return {v.x(), v.y(), 0.0}; }

}  // namespace

ImageRotation image_rotation(const Eigen::Matrix3d& Q, const Eigen::Matrix3d& dQ, const Eigen::Matrix3d& d2Q,
                             const Eigen::Vector3d& w_master, const Eigen::Vector3d& near) {
  const rigid::RotationDerivatives Ri = rigid::rotation_derivatives(w_master);
  ImageRotation out;
  out.w = rigid::rotation_vector(Q * Ri.rotation, near);
  const rigid::RotationDerivatives Rj = rigid::rotation_derivatives(out.w);
  Eigen::Matrix3d J;  // [J_m] = dR/dw_m R^T: columns J_m
  for (int m = 0; m < 3; ++m)
    J.col(m) = rigid::skew_vee(Rj.first[static_cast<std::size_t>(m)] * Rj.rotation.transpose());
  const Eigen::Matrix3d J_inverse = J.inverse();
  // P(z) = Q(kappa) R(w_i): first derivatives in z = (w_i, kappa).
  std::array<Eigen::Matrix3d, 4> dP;
  for (std::size_t k = 0; k < 3; ++k) dP[k] = Q * Ri.first[k];
  dP[3] = dQ * Ri.rotation;
  for (int a = 0; a < 4; ++a)
    out.jacobian.col(a) = J_inverse * rigid::skew_vee(dP[static_cast<std::size_t>(a)] * Rj.rotation.transpose());
  for (int a = 0; a < 4; ++a)
    for (int b = a; b < 4; ++b) {
      Eigen::Matrix3d d2P;
      if (a < 3 && b < 3) d2P = Q * Ri.second[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)];
      else if (a < 3) d2P = dQ * Ri.first[static_cast<std::size_t>(a)];
      else d2P = d2Q * Ri.rotation;
      // Subtract the second derivative of R(w_j) along the first-order motion of w_j.
      for (int m = 0; m < 3; ++m)
        for (int n = 0; n < 3; ++n)
          d2P -= Rj.second[static_cast<std::size_t>(m)][static_cast<std::size_t>(n)] *
                 (out.jacobian(m, a) * out.jacobian(n, b));
      const Eigen::Vector3d column = J_inverse * rigid::skew_vee(d2P * Rj.rotation.transpose());
      for (int m = 0; m < 3; ++m) {
        out.hessian[static_cast<std::size_t>(m)](a, b) = column[m];
        out.hessian[static_cast<std::size_t>(m)](b, a) = column[m];
      }
    }
  return out;
}

CylinderScrew cylinder_screw(double kappa, double angle, const Eigen::Vector3d& anchor, const Eigen::Vector2d& shift) {
  const Eigen::Vector3d d(std::cos(angle), std::sin(angle), 0.0), e(-std::sin(angle), std::cos(angle), 0.0);
  const Eigen::Vector3d a = d.cross(Eigen::Vector3d::UnitZ());
  const double u = d.dot(plane_vector(shift)), v = e.dot(plane_vector(shift));
  const ArcCoefficients arc = arc_coefficients(kappa * u);
  const Eigen::Matrix3d A = rigid::cross_matrix(a);
  CylinderScrew s;
  s.axis_rate = u * a;
  s.Q = rigid::rotation_matrix(kappa * s.axis_rate);
  s.dQ = u * A * s.Q;
  s.d2Q = u * u * A * A * s.Q;
  s.b = anchor - s.Q * anchor + u * (arc.h1 * d + arc.h2 * Eigen::Vector3d::UnitZ()) + v * e;
  s.db = -s.dQ * anchor + u * u * (arc.dh1 * d + arc.dh2 * Eigen::Vector3d::UnitZ());
  return s;
}

SingleCurvatureCell::SingleCurvatureCell(const PeriodicRigidCell& cell, double angle) : cell_(&cell), angle_(angle) {
  if (cell.spec().bending_patch)
    throw std::invalid_argument("single curvature: needs a periodic cell, not a bending patch");
  if (!std::isfinite(angle)) throw std::invalid_argument("single curvature: the angle must be finite");
  const int n = cell.num_elements();
  column_.assign(static_cast<std::size_t>(6 * n), -1);
  const SparseMatrix& S = cell.basis();
  for (int k = 0; k < S.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(S, k); it; ++it)
      if (it.row() < 6 * n) column_[static_cast<std::size_t>(it.row())] = static_cast<int>(it.col());
}

Eigen::Matrix2d SingleCurvatureCell::deformation(double kappa) const {
  const Eigen::Vector2d d(std::cos(angle_), std::sin(angle_));
  return Eigen::Matrix2d::Identity() + kappa * d * d.transpose();
}

std::vector<CylinderScrew> SingleCurvatureCell::screws(double kappa) const {
  const PeriodicRigidCell& cell = *cell_;
  const Eigen::Vector3d anchor = cell.spec().elements[static_cast<std::size_t>(cell.spec().anchor)].position;
  std::vector<CylinderScrew> out;
  for (int body = cell.num_elements(); body < cell.num_bodies(); ++body)
    out.push_back(cylinder_screw(kappa, angle_, anchor, cell.spec().lattice * cell.shift(body).cast<double>()));
  return out;
}

Vector SingleCurvatureCell::full_state(const Vector& y, double kappa) const {
  const PeriodicRigidCell& cell = *cell_;
  const int n = cell.num_elements();
  Vector x(6 * cell.num_bodies());
  x.head(6 * n) = cell.master_state(y);
  const std::vector<CylinderScrew> s = screws(kappa);
  for (int body = n; body < cell.num_bodies(); ++body) {
    const CylinderScrew& screw = s[static_cast<std::size_t>(body - n)];
    const int i = cell.master(body);
    const Eigen::Vector3d w = x.segment<3>(6 * i + 3);
    x.segment<3>(6 * body) = screw.Q * x.segment<3>(6 * i) + screw.b;
    x.segment<3>(6 * body + 3) = rigid::rotation_vector(screw.Q * rigid::rotation_matrix(w), w + kappa * screw.axis_rate);
  }
  return x;
}

SingleCurvatureCell::MapDerivatives SingleCurvatureCell::map(const Vector& y, double kappa) const {
  const PeriodicRigidCell& cell = *cell_;
  const int n = cell.num_elements(), nb = cell.num_bodies();
  MapDerivatives m;
  m.x.resize(6 * nb);
  m.x.head(6 * n) = cell.master_state(y);
  m.curvature_derivative = Vector::Zero(6 * nb);
  Triplets t;
  for (int row = 0; row < 6 * n; ++row)
    if (column_[static_cast<std::size_t>(row)] >= 0) t.emplace_back(row, column_[static_cast<std::size_t>(row)], 1.0);
  const std::vector<CylinderScrew> s = screws(kappa);
  for (int body = n; body < nb; ++body) {
    const CylinderScrew& screw = s[static_cast<std::size_t>(body - n)];
    const int i = cell.master(body);
    const Eigen::Vector3d T = m.x.segment<3>(6 * i), w = m.x.segment<3>(6 * i + 3);
    const ImageRotation r = image_rotation(screw.Q, screw.dQ, screw.d2Q, w, w + kappa * screw.axis_rate);
    m.x.segment<3>(6 * body) = screw.Q * T + screw.b;
    m.x.segment<3>(6 * body + 3) = r.w;
    m.curvature_derivative.segment<3>(6 * body) = screw.dQ * T + screw.db;
    m.curvature_derivative.segment<3>(6 * body + 3) = r.jacobian.col(3);
    for (int row = 0; row < 3; ++row)
      for (int c = 0; c < 3; ++c) {
        const int col_T = column_[static_cast<std::size_t>(6 * i + c)], col_w = column_[static_cast<std::size_t>(6 * i + 3 + c)];
        if (col_T >= 0) t.emplace_back(6 * body + row, col_T, screw.Q(row, c));
        if (col_w >= 0) t.emplace_back(6 * body + 3 + row, col_w, r.jacobian(row, c));
      }
    m.rotations.push_back(r);
    m.rotation_rate.push_back(screw.dQ);
  }
  m.jacobian.resize(6 * nb, cell.num_free());
  m.jacobian.setFromTriplets(t.begin(), t.end());
  return m;
}

SingleCurvatureCell::Reduced SingleCurvatureCell::reduce(const Vector& y, double kappa, bool hessian,
                                                         HessianMode mode) const {
  const PeriodicRigidCell& cell = *cell_;
  const int n = cell.num_elements();
  MapDerivatives m = map(y, kappa);
  // Projected: the per-pair PSD projection through the Jacobian, J^T H+ J, without the map's
  // curvature term (a Gauss-Newton matrix for Newton; the exact Hessian for derivatives).
  const ReducedContact c = reduced_contact(cell, m.x, hessian, mode);
  Reduced r;
  r.energy = c.energy;
  r.x = std::move(m.x);
  if (!std::isfinite(c.energy)) return r;
  r.full_gradient = c.full_gradient;
  r.gradient = m.jacobian.transpose() * c.full_gradient;
  r.curvature_derivative = m.curvature_derivative;
  r.curvature_gradient = c.full_gradient.dot(m.curvature_derivative);
  r.jacobian = m.jacobian;
  if (!hessian) return r;
  r.full_hessian = c.full_hessian;
  const SparseMatrix JtH = m.jacobian.transpose() * c.full_hessian;
  r.hessian = Matrix(JtH * m.jacobian);
  r.mixed = JtH * m.curvature_derivative;
  if (mode == HessianMode::projected) return r;
  // The images' rotation rows: their second derivatives in (w_i, kappa) weighted by g.
  for (int body = n; body < cell.num_bodies(); ++body) {
    const ImageRotation& rot = m.rotations[static_cast<std::size_t>(body - n)];
    const int i = cell.master(body);
    const Eigen::Vector3d g_w = c.full_gradient.segment<3>(6 * body + 3), g_T = c.full_gradient.segment<3>(6 * body);
    Eigen::Matrix4d weighted = Eigen::Matrix4d::Zero();
    for (std::size_t k = 0; k < 3; ++k) weighted += g_w[static_cast<Eigen::Index>(k)] * rot.hessian[k];
    const Eigen::Vector3d dQ_t_g = m.rotation_rate[static_cast<std::size_t>(body - n)].transpose() * g_T;
    for (int k = 0; k < 3; ++k) {
      const int col_w = column_[static_cast<std::size_t>(6 * i + 3 + k)], col_T = column_[static_cast<std::size_t>(6 * i + k)];
      if (col_T >= 0) r.mixed[col_T] += dQ_t_g[k];
      if (col_w < 0) continue;
      r.mixed[col_w] += weighted(k, 3);
      for (int l = 0; l < 3; ++l) {
        const int col_l = column_[static_cast<std::size_t>(6 * i + 3 + l)];
        if (col_l >= 0) r.hessian(col_w, col_l) += weighted(k, l);
      }
    }
  }
  return r;
}

Vector SingleCurvatureCell::bend_masters(const Vector& y, double kappa_old, double kappa_new) const {
  const PeriodicRigidCell& cell = *cell_;
  const Eigen::Vector3d anchor = cell.spec().elements[static_cast<std::size_t>(cell.spec().anchor)].position;
  const Eigen::Vector3d d(std::cos(angle_), std::sin(angle_), 0.0), e(-std::sin(angle_), std::cos(angle_), 0.0);
  Vector q = cell.master_state(y);
  for (int i = 0; i < cell.num_elements(); ++i) {
    const Eigen::Vector3d rel = q.segment<3>(6 * i) - anchor;
    const double v = e.dot(rel), x_d = d.dot(rel), z = rel.z();
    // Arc coordinates on the old cylinder: the point is (rho sin(phi), 1/kappa - rho cos(phi)) in
    // the (d, z) plane with rho = 1/kappa - h and phi = kappa u.
    double u = x_d, h = z;
    if (std::abs(kappa_old) > 1e-8) {
      const double radius = 1.0 / kappa_old, sign = kappa_old > 0.0 ? 1.0 : -1.0;
      const double phi = std::atan2(sign * x_d, sign * (radius - z));
      u = phi / kappa_old;
      h = radius - sign * std::hypot(x_d, radius - z);
    }
    const Eigen::Vector2d shift = u * d.head<2>() + v * e.head<2>();
    const CylinderScrew s_old = cylinder_screw(kappa_old, angle_, anchor, shift);
    const CylinderScrew s_new = cylinder_screw(kappa_new, angle_, anchor, shift);
    const Eigen::Vector3d w = q.segment<3>(6 * i + 3);
    q.segment<3>(6 * i) = s_new.Q * (anchor + h * Eigen::Vector3d::UnitZ()) + s_new.b;
    q.segment<3>(6 * i + 3) =
        rigid::rotation_vector(s_new.Q * s_old.Q.transpose() * rigid::rotation_matrix(w), w);
  }
  return cell.basis().topRows(6 * cell.num_elements()).transpose() * q;
}

void SingleCurvatureContactTerm::evaluate(const Vector& y, const Vector& p, const EnergyRequest& request) const {
  const bool hessian = request.hessian_values != nullptr;
  const SingleCurvatureCell::Reduced r = cell_->reduce(y, p[0], hessian, request.hessian_mode);
  if (request.value) *request.value += r.energy;
  if (!std::isfinite(r.energy)) return;
  if (request.gradient) *request.gradient += r.gradient;
  if (hessian) {
    const int n = static_cast<int>(y.size());
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) request.hessian_values[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = r.hessian(i, j);
  }
}

void SingleCurvatureContactTerm::hessian_pattern(HessianPattern& pattern) const {
  const int n = cell_->num_free();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) pattern.push_back({i, j});
}

void SingleCurvatureContactTerm::add_param_gradient(const Vector& y, const Vector& p, Vector& gradient_p) const {
  const SingleCurvatureCell::Reduced r = cell_->reduce(y, p[0], false);
  if (std::isfinite(r.energy)) gradient_p[0] += r.curvature_gradient;
}

void SingleCurvatureContactTerm::add_mixed(const Vector& y, const Vector& p, Triplets& mixed) const {
  const SingleCurvatureCell::Reduced r = cell_->reduce(y, p[0], true);
  if (!std::isfinite(r.energy)) return;
  for (int i = 0; i < r.mixed.size(); ++i)
    if (r.mixed[i] != 0.0) mixed.emplace_back(i, 0, r.mixed[i]);
}

}  // namespace tailor::interlocking
