#pragma once
// The per-element math of the descent solver's vertex-block rule, written once for the host and
// the CUDA device (docs/dynamics.md, "The GPU path"): for one linear tet with rest shape
// gradients G (row a = grad N_a, 4 x 3 row-major), rest volume V and Lame parameters (lambda, mu),
// at vertex positions x_a, the energy V Psi(F), the gradient V P g_a per vertex and the 3 x 3
// diagonal blocks d2E/dx_a^2 of its Hessian, each projected to PSD on its own (the cheap rule
// the device can run; the CPU's default projects the whole 12 x 12 element tangent instead).
// Materials: the stable Neo-Hookean of forward/fem/materials/neo_hookean.hpp and Saint
// Venant-Kirchhoff (stvk.hpp), in the same expanded forms, so the host instantiation equals the
// element loop's values to round-off (tests/forward/dynamics/descent_kernels_test.cpp).
//
// Fixed-size plain arrays only (no Eigen), so the header costs g++ little and compiles under
// nvcc; TAILOR_HOST_DEVICE is __host__ __device__ there and empty elsewhere.
#include <math.h>

#ifdef __CUDACC__
#define TAILOR_HOST_DEVICE __host__ __device__
#else
#define TAILOR_HOST_DEVICE
#endif

namespace tailor::descent_kernels {

enum TetMaterial : int { kNeoHookean = 0, kStvk = 1 };

// F = sum_a x_a g_a^T (row-major 3 x 3); x: 4 positions of 3, G: 4 x 3 row-major.
TAILOR_HOST_DEVICE inline void deformation_gradient(const double* x, const double* G, double* F) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      F[3 * i + j] = x[i] * G[j] + x[3 + i] * G[3 + j] + x[6 + i] * G[6 + j] + x[9 + i] * G[9 + j];
}

// cof F = dJ/dF (row-major), and J = det F.
TAILOR_HOST_DEVICE inline double cofactor(const double* F, double* C) {
  C[0] = F[4] * F[8] - F[5] * F[7];
  C[1] = F[5] * F[6] - F[3] * F[8];
  C[2] = F[3] * F[7] - F[4] * F[6];
  C[3] = F[2] * F[7] - F[1] * F[8];
  C[4] = F[0] * F[8] - F[2] * F[6];
  C[5] = F[1] * F[6] - F[0] * F[7];
  C[6] = F[1] * F[5] - F[2] * F[4];
  C[7] = F[2] * F[3] - F[0] * F[5];
  C[8] = F[0] * F[4] - F[1] * F[3];
  return F[0] * C[0] + F[1] * C[1] + F[2] * C[2];
}

// out = M v (3 x 3 row-major M).
TAILOR_HOST_DEVICE inline void times(const double* M, const double* v, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = M[3 * i] * v[0] + M[3 * i + 1] * v[1] + M[3 * i + 2] * v[2];
}

// Replaces the symmetric 3 x 3 A (row-major) by its PSD part: unchanged when its leading minors
// are positive (Sylvester), else the negative eigenvalues are set to zero, eigenvectors by cyclic
// Jacobi rotations (a fixed maximum of sweeps; each sweep squares the off-diagonal's size).
TAILOR_HOST_DEVICE inline void project_psd(double* A) {
  const double m1 = A[0], m2 = A[0] * A[4] - A[1] * A[3];
  const double m3 = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
                    A[2] * (A[3] * A[7] - A[4] * A[6]);
  if (m1 > 0.0 && m2 > 0.0 && m3 > 0.0) return;
  double a[9], v[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int k = 0; k < 9; ++k) a[k] = A[k];
  const double scale = fabs(a[0]) + fabs(a[4]) + fabs(a[8]) + fabs(a[1]) + fabs(a[2]) + fabs(a[5]);
  for (int sweep = 0; sweep < 16; ++sweep) {
    const double off = fabs(a[1]) + fabs(a[2]) + fabs(a[5]);
    if (!(off > 1e-17 * scale)) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const double apq = a[3 * p + q];
        if (apq == 0.0) continue;
        // The rotation that zeroes a_pq: t = tan(theta), the smaller root of t^2 + 2 tau t - 1 = 0.
        const double tau = (a[3 * q + q] - a[3 * p + p]) / (2.0 * apq);
        const double t = (tau >= 0.0 ? 1.0 : -1.0) / (fabs(tau) + sqrt(1.0 + tau * tau));
        const double c = 1.0 / sqrt(1.0 + t * t), s = t * c;
        for (int k = 0; k < 3; ++k) {  // a <- a R (columns p, q)
          const double akp = a[3 * k + p], akq = a[3 * k + q];
          a[3 * k + p] = c * akp - s * akq;
          a[3 * k + q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // a <- R^T a (rows p, q)
          const double apk = a[3 * p + k], aqk = a[3 * q + k];
          a[3 * p + k] = c * apk - s * aqk;
          a[3 * q + k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {  // v <- v R: columns are the eigenvectors
          const double vkp = v[3 * k + p], vkq = v[3 * k + q];
          v[3 * k + p] = c * vkp - s * vkq;
          v[3 * k + q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += v[3 * i + k] * (a[4 * k] > 0.0 ? a[4 * k] : 0.0) * v[3 * j + k];
      A[3 * i + j] = s;
    }
}

// One tet: the energy V Psi, gradient (when gradient != nullptr: 12 values, vertex a at 3a) and
// the diagonal Hessian blocks (when blocks != nullptr: 4 blocks of 9, row-major, each projected
// by project_psd when `project`). lambda, mu: physical Lame parameters [Pa]; positions [m].
TAILOR_HOST_DEVICE inline double tet_element(int material, const double* x, const double* G, double V, double lambda,
                                             double mu, double* gradient, double* blocks, bool project) {
  double F[9], C[9];
  deformation_gradient(x, G, F);
  const double J = cofactor(F, C);
  double energy, P[9];
  if (material == kNeoHookean) {
    // Psi = (2/3) mu (x - log(1 + x/4)) + lambda'/2 (J - 1)^2 - mu (J - 1), x = I_C - 3 formed as
    // |F - I|^2 + 2 tr(F - I) (neo_hookean.hpp), lambda' = lambda + 5/6 mu, mu' = 4/3 mu.
    const double mu_s = 4.0 / 3.0 * mu, lambda_s = lambda + 5.0 / 6.0 * mu;
    double xi = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double d = F[3 * i + j] - (i == j ? 1.0 : 0.0);
        xi += d * d;
      }
    xi += 2.0 * (F[0] + F[4] + F[8] - 3.0);
    const double Ic = xi + 3.0, Jm1 = J - 1.0;
    energy = V * (0.5 * mu_s * (xi - log1p(0.25 * xi)) + 0.5 * lambda_s * Jm1 * Jm1 - mu * Jm1);
    const double a = mu_s * Ic / (Ic + 1.0), s = lambda_s * Jm1 - mu;
    for (int k = 0; k < 9; ++k) P[k] = a * F[k] + s * C[k];
    if (blocks) {
      // Block (a, a) = V [a |g|^2 I + b (F g)(F g)^T + lambda' (C g)(C g)^T]: the determinant's
      // second derivative contracts to g x g = 0 on the diagonal (neo_hookean.hpp).
      const double b = 2.0 * mu_s / ((Ic + 1.0) * (Ic + 1.0));
      for (int n = 0; n < 4; ++n) {
        const double* g = G + 3 * n;
        double Fg[3], Cg[3];
        times(F, g, Fg);
        times(C, g, Cg);
        const double gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        double* B = blocks + 9 * n;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            B[3 * i + j] = V * (b * Fg[i] * Fg[j] + lambda_s * Cg[i] * Cg[j] + (i == j ? a * gg : 0.0));
      }
    }
  } else {
    // Psi = lambda/2 tr(E)^2 + mu |E|^2, E = (F^T F - I)/2, P = F S, S = lambda tr(E) I + 2 mu E.
    double E[9], S[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        E[3 * i + j] = 0.5 * (F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j] - (i == j ? 1.0 : 0.0));
    const double tr = E[0] + E[4] + E[8];
    double EE = 0.0;
    for (int k = 0; k < 9; ++k) EE += E[k] * E[k];
    energy = V * (0.5 * lambda * tr * tr + mu * EE);
    for (int k = 0; k < 9; ++k) S[k] = 2.0 * mu * E[k] + (k % 4 == 0 ? lambda * tr : 0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        P[3 * i + j] = F[3 * i] * S[j] + F[3 * i + 1] * S[3 + j] + F[3 * i + 2] * S[6 + j];
    if (blocks) {
      // Block (a, a) = V [(g^T S g) I + (lambda + mu)(F g)(F g)^T + mu |g|^2 F F^T], from
      // dP_ij/dF_kl = d_ik S_lj + lambda F_ij F_kl + mu d_jl (F F^T)_ik + mu F_il F_kj (stvk.hpp).
      for (int n = 0; n < 4; ++n) {
        const double* g = G + 3 * n;
        double Fg[3], Sg[3];
        times(F, g, Fg);
        times(S, g, Sg);
        const double gSg = g[0] * Sg[0] + g[1] * Sg[1] + g[2] * Sg[2];
        const double gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        double* B = blocks + 9 * n;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const double FFt = F[3 * i] * F[3 * j] + F[3 * i + 1] * F[3 * j + 1] + F[3 * i + 2] * F[3 * j + 2];
            B[3 * i + j] = V * ((lambda + mu) * Fg[i] * Fg[j] + mu * gg * FFt + (i == j ? gSg : 0.0));
          }
      }
    }
  }
  if (gradient)
    for (int n = 0; n < 4; ++n) times(P, G + 3 * n, gradient + 3 * n);
  if (gradient)
    for (int k = 0; k < 12; ++k) gradient[k] *= V;
  if (blocks && project)
    for (int n = 0; n < 4; ++n) project_psd(blocks + 9 * n);
  return energy;
}

// Inverse of the SPD n x n matrix a (row-major, n <= 3) by Cholesky into inv; false (inv
// untouched) when a pivot is not positive.
TAILOR_HOST_DEVICE inline bool invert_spd(const double* a, int n, double* inv) {
  double l[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (int j = 0; j < n; ++j) {
    double d = a[j * n + j];
    for (int k = 0; k < j; ++k) d -= l[j * 3 + k] * l[j * 3 + k];
    if (!(d > 0.0)) return false;
    l[j * 3 + j] = sqrt(d);
    for (int i = j + 1; i < n; ++i) {
      double s = a[i * n + j];
      for (int k = 0; k < j; ++k) s -= l[i * 3 + k] * l[j * 3 + k];
      l[i * 3 + j] = s / l[j * 3 + j];
    }
  }
  // inv = L^-T L^-1, column by column of the identity.
  for (int c = 0; c < n; ++c) {
    double z[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {  // L z = e_c
      double s = i == c ? 1.0 : 0.0;
      for (int k = 0; k < i; ++k) s -= l[i * 3 + k] * z[k];
      z[i] = s / l[i * 3 + i];
    }
    for (int i = n - 1; i >= 0; --i) {  // L^T w = z
      double s = z[i];
      for (int k = i + 1; k < n; ++k) s -= l[k * 3 + i] * inv[k * n + c];
      inv[i * n + c] = s / l[i * 3 + i];
    }
  }
  return true;
}

// The block inverse of the preconditioner from the summed block a (n x n, n <= 3, row-major):
// the Cholesky inverse, or where a is not positive definite (a vertex without mass or stiffness)
// the inverse of its absolute diagonal, floored at 1e-12 of the largest, which keeps D^-1 g a
// descent direction.
TAILOR_HOST_DEVICE inline void block_inverse(const double* a, int n, double* inv) {
  if (invert_spd(a, n, inv)) return;
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = fabs(a[i * n + i]) > scale ? fabs(a[i * n + i]) : scale;
  double floor = scale * 1e-12;
  if (!(floor > 2.2250738585072014e-308)) floor = 2.2250738585072014e-308;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double d = fabs(a[i * n + i]);
      inv[i * n + j] = i == j ? 1.0 / (d > floor ? d : floor) : 0.0;
    }
}

}  // namespace tailor::descent_kernels
