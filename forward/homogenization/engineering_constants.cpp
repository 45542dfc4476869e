#include "forward/homogenization/engineering_constants.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace tailor {
namespace {

int dim_of_voigt(int size) {
  if (size == 3) return 2;
  if (size == 6) return 3;
  throw std::invalid_argument("Voigt vectors have 3 (2D) or 6 (3D) entries, got " + std::to_string(size));
}

void check_direction(const Matrix& S, const Vector& d, const char* who) {
  const int dim = dim_of_voigt(static_cast<int>(S.rows()));
  if (d.size() != dim || !(d.norm() > 0.0))
    throw std::invalid_argument(std::string(who) + ": need a nonzero direction of size " +
                                std::to_string(dim));
}

}  // namespace

Vector voigt_stress(const Matrix& T) {
  if (T.rows() == 2 && T.cols() == 2) return Vector{{T(0, 0), T(1, 1), 0.5 * (T(0, 1) + T(1, 0))}};
  if (T.rows() == 3 && T.cols() == 3)
    return Vector{{T(0, 0), T(1, 1), T(2, 2), 0.5 * (T(1, 2) + T(2, 1)), 0.5 * (T(0, 2) + T(2, 0)),
                   0.5 * (T(0, 1) + T(1, 0))}};
  throw std::invalid_argument("voigt_stress: need a 2 x 2 or 3 x 3 tensor");
}

Matrix strain_from_voigt(const Vector& v) {
  const int dim = dim_of_voigt(static_cast<int>(v.size()));
  Matrix T(dim, dim);
  if (dim == 2) {
    T << v[0], 0.5 * v[2], 0.5 * v[2], v[1];
  } else {
    T << v[0], 0.5 * v[5], 0.5 * v[4], 0.5 * v[5], v[1], 0.5 * v[3], 0.5 * v[4], 0.5 * v[3], v[2];
  }
  return T;
}

Matrix compliance(const Matrix& stiffness) {
  if (stiffness.rows() != stiffness.cols()) throw std::invalid_argument("compliance: C must be square");
  dim_of_voigt(static_cast<int>(stiffness.rows()));
  const Eigen::FullPivLU<Matrix> lu(stiffness);
  if (!lu.isInvertible()) throw std::invalid_argument("compliance: the stiffness tensor is singular");
  return lu.inverse();
}

double directional_youngs_modulus(const Matrix& S, const Vector& d) {
  check_direction(S, d, "directional_youngs_modulus");
  const Vector a = voigt_stress(d.normalized() * d.normalized().transpose());
  return 1.0 / a.dot(S * a);
}

double poisson_ratio(const Matrix& S, const Vector& d, const Vector& n) {
  check_direction(S, d, "poisson_ratio");
  check_direction(S, n, "poisson_ratio");
  const Vector a = voigt_stress(d.normalized() * d.normalized().transpose());
  const Vector b = voigt_stress(n.normalized() * n.normalized().transpose());
  return -b.dot(S * a) / a.dot(S * a);
}

double shear_modulus(const Matrix& S, const Vector& d, const Vector& n) {
  check_direction(S, d, "shear_modulus");
  check_direction(S, n, "shear_modulus");
  const Vector dn = d.normalized(), nn = n.normalized();
  const Vector c = voigt_stress(dn * nn.transpose() + nn * dn.transpose());
  return 1.0 / c.dot(S * c);
}

Matrix isotropic_stiffness(int dim, double E, double nu, bool plane_stress) {
  if (dim != 2 && dim != 3) throw std::invalid_argument("isotropic_stiffness: dim must be 2 or 3");
  if (plane_stress && dim != 2) throw std::invalid_argument("isotropic_stiffness: plane stress is 2D only");
  const double mu = E / (2.0 * (1.0 + nu));
  const double lambda = plane_stress ? E * nu / (1.0 - nu * nu) : E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const int m = dim == 2 ? 3 : 6;
  Matrix C = Matrix::Zero(m, m);
  for (int i = 0; i < dim; ++i) {
    for (int j = 0; j < dim; ++j) C(i, j) = lambda;
    C(i, i) = lambda + 2.0 * mu;
  }
  for (int i = dim; i < m; ++i) C(i, i) = mu;
  return C;
}

Vector plane_direction(int dim, int i, int j, double theta) {
  Vector d = Vector::Zero(dim);
  d[i] = std::cos(theta);
  d[j] = std::sin(theta);
  return d;
}

}  // namespace tailor
