// Rodrigues' rotation with exact derivatives (see rotation.hpp).
#include "forward/rigid/rotation.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "forward/core/dual2.hpp"

namespace tailor::rigid {

RodriguesCoefficients rodrigues_coefficients(double s) {
  RodriguesCoefficients c{};
  if (s < 1.0) {
    // a = sum_k (-1)^k s^k / (2k+1)!,  b = sum_k (-1)^k s^k / (2k+2)!; 12 terms leave a
    // truncation error below 1e-25 for s < 1.
    double fa = 1.0, fb = 0.5;            // (-1)^k / (2k+1)! and (-1)^k / (2k+2)!
    double p0 = 1.0, p1 = 0.0, p2 = 0.0;  // s^k, k s^(k-1), k (k-1) s^(k-2)
    double sk1 = 0.0, sk2 = 0.0;          // s^(k-1), s^(k-2)
    for (int k = 0; k < 12; ++k) {
      c.a += fa * p0;
      c.da += fa * p1;
      c.d2a += fa * p2;
      c.b += fb * p0;
      c.db += fb * p1;
      c.d2b += fb * p2;
      // advance to k + 1
      sk2 = sk1;
      sk1 = p0;
      p0 *= s;
      p1 = (k + 1) * sk1;
      p2 = (k + 1) * k * sk2;
      fa /= -((2.0 * k + 2) * (2.0 * k + 3));
      fb /= -((2.0 * k + 3) * (2.0 * k + 4));
    }
    return c;
  }
  const double t = std::sqrt(s), sn = std::sin(t), cs = std::cos(t);
  const double t2 = t * t, t3 = t2 * t, t4 = t3 * t;
  c.a = sn / t;
  const double a_t = cs / t - sn / t2;
  const double a_tt = -sn / t - 2.0 * cs / t2 + 2.0 * sn / t3;
  c.b = (1.0 - cs) / t2;
  const double b_t = sn / t2 - 2.0 * (1.0 - cs) / t3;
  const double b_tt = cs / t2 - 4.0 * sn / t3 + 6.0 * (1.0 - cs) / t4;
  // d/ds = (1 / 2t) d/dt;  d2/ds2 = (f_tt - f_t / t) / (4 t^2).
  c.da = a_t / (2.0 * t);
  c.d2a = (a_tt - a_t / t) / (4.0 * t2);
  c.db = b_t / (2.0 * t);
  c.d2b = (b_tt - b_t / t) / (4.0 * t2);
  return c;
}

Eigen::Matrix3d rotation_matrix(const Eigen::Vector3d& w) {
  const RodriguesCoefficients c = rodrigues_coefficients(w.squaredNorm());
  Eigen::Matrix3d K;
  K << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return Eigen::Matrix3d::Identity() + c.a * K + c.b * K * K;
}

RotationDerivatives rotation_derivatives(const Eigen::Vector3d& w) {
  using J = Dual2<3>;
  const std::array<J, 3> wj{J::variable(w.x(), 0), J::variable(w.y(), 1), J::variable(w.z(), 2)};
  const J s = wj[0] * wj[0] + wj[1] * wj[1] + wj[2] * wj[2];
  const RodriguesCoefficients c = rodrigues_coefficients(s.v);
  const J a = chain(s, c.a, c.da, c.d2a), b = chain(s, c.b, c.db, c.d2b);
  // [w]_ij = -eps_ijk w_k;  ([w]^2)_ij = w_i w_j - delta_ij s.
  const J zero(0.0);
  const std::array<std::array<J, 3>, 3> K{
      {{zero, -wj[2], wj[1]}, {wj[2], zero, -wj[0]}, {-wj[1], wj[0], zero}}};
  RotationDerivatives r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      J kk = wj[i] * wj[j];
      if (i == j) kk = kk - s;
      J entry = a * K[i][j] + b * kk;
      entry.v += (i == j) ? 1.0 : 0.0;
      r.rotation(i, j) = entry.v;
      for (int k = 0; k < 3; ++k) {
        r.first[k](i, j) = entry.g[k];
        for (int l = 0; l < 3; ++l) r.second[k][l](i, j) = entry.h(k, l);
      }
    }
  return r;
}

Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R, const Eigen::Vector3d& near) {
  const Eigen::AngleAxisd axis_angle(R);
  Eigen::Vector3d w = axis_angle.angle() * axis_angle.axis();
  if (!(w.norm() > 0.0)) return w;
  const Eigen::Vector3d unit = w.normalized();
  for (double k : {-1.0, 1.0}) {
    const Eigen::Vector3d other = w + k * 2.0 * M_PI * unit;
    if (other.norm() < 2.0 * M_PI && (other - near).norm() < (w - near).norm()) w = other;
  }
  return w;
}

}  // namespace tailor::rigid
