// The rig's skinning, pose weights and keyframes with their exact derivatives (central
// differences, each check also shown to fail on a derivative scaled by 1.001), orthogonal
// Procrustes, pose-space blending, and constrained modes against a dense Lagrange-multiplier
// solve (reduced to a standard symmetric eigenproblem, forward/core's compiled-once solver: no
// general or generalized dense eigensolver is instantiated here).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "adjoint/derivative_check.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/fem/mass.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/reduction/constrained_modes.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/rig/pose_space_basis.hpp"
#include "forward/rig/two_bone_arm.hpp"

namespace tailor::rig::rig_test {
namespace {

// Three bones in a chain with translations and rotations about tilted axes, random weights over
// the bones and three pose corrections: every branch of the derivatives is exercised.
Rig chain_rig(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 0.5, 0.4), 6, 1, 1);
  const int n = mesh.num_vertices();
  std::vector<Bone> bones(3);
  bones[0] = {"root", -1, Eigen::Vector3d(0.1, 0.2, 0.0),
              {{BoneDofType::translation, Eigen::Vector3d(1, 2, 2).normalized()},
               {BoneDofType::rotation, Eigen::Vector3d(0.3, 0.4, 1).normalized()}}};
  bones[1] = {"middle", 0, Eigen::Vector3d(1.0, 0.25, 0.2),
              {{BoneDofType::rotation, Eigen::Vector3d::UnitZ()}, {BoneDofType::rotation, Eigen::Vector3d(1, -1, 0.5).normalized()}}};
  bones[2] = {"tip", 1, Eigen::Vector3d(2.0, 0.25, 0.2), {{BoneDofType::rotation, Eigen::Vector3d(0, 1, 0.2).normalized()}}};
  Matrix weights(n, 3);
  for (int v = 0; v < n; ++v) {
    weights.row(v) << uniform(rng), uniform(rng), uniform(rng);
    weights.row(v) /= weights.row(v).sum();
  }
  std::vector<PoseCorrection> corrections;
  for (int i = 0; i < 3; ++i) {
    PoseCorrection c;
    c.pose = Vector::Random(5);
    c.displacement = 0.05 * Matrix::Random(n, 3);
    corrections.push_back(c);
  }
  return Rig(std::move(bones), mesh.rest_positions, weights, std::move(corrections));
}

DerivativeCheckOptions check_options() {
  DerivativeCheckOptions o;
  o.initial_step = 1e-2;
  o.tolerance = 1e-7;
  return o;
}

// Passes as given, fails when the analytic derivative is scaled by 1.001.
void expect_derivative(const std::string& what, const std::function<Vector(double)>& f, const Vector& analytic) {
  const DerivativeCheck good = check_directional_derivative(what, f, analytic, check_options());
  EXPECT_TRUE(good.passed) << what << ": " << good.message << " best error " << good.best_error;
  const DerivativeCheck bad = check_directional_derivative(what, f, 1.001 * analytic, check_options());
  EXPECT_FALSE(bad.passed) << what << " passes with a wrong derivative";
}

TEST(RigDerivatives, SkinningJacobianAndSecondDerivativesMatchDifferences) {
  const Rig rig = chain_rig(3);
  ASSERT_EQ(rig.num_parameters(), 5);
  const Vector p = 0.7 * Vector::Random(5), dp = Vector::Random(5), a = Vector::Random(5);
  expect_derivative("dX/dp", [&](double t) { return rig.rest_shape(p + t * dp); }, rig.rest_shape_jacobian(p) * dp);
  expect_derivative("d2X/dp2", [&](double t) { return Vector(rig.rest_shape_jacobian(p + t * dp) * a); },
                    rig.rest_shape_second(p, a, dp));
  // The same without corrections: the bone chain alone.
  const Rig bare(rig.bones(), rig.rest_positions(), rig.weights());
  expect_derivative("dX/dp (bones only)", [&](double t) { return bare.rest_shape(p + t * dp); },
                    bare.rest_shape_jacobian(p) * dp);
  expect_derivative("d2X/dp2 (bones only)", [&](double t) { return Vector(bare.rest_shape_jacobian(p + t * dp) * a); },
                    bare.rest_shape_second(p, a, dp));
}

TEST(RigDerivatives, RestShapeAccelerationAlongKeyframesMatchesDifferences) {
  const Rig rig = chain_rig(5);
  std::vector<Vector> poses = {Vector::Zero(5), 0.5 * Vector::Random(5), 0.5 * Vector::Random(5), Vector::Random(5)};
  const PoseTrajectory trajectory({0.0, 0.3, 0.7, 1.0}, poses);
  const double t0 = 0.5;
  const PoseMotion m = trajectory(t0);
  expect_derivative("dp/dt", [&](double t) { return trajectory(t0 + t).p; }, m.velocity);
  expect_derivative("d2p/dt2", [&](double t) { return trajectory(t0 + t).velocity; }, m.acceleration);
  // d/dt (J(p(t)) p'(t)) = d2X/dt2.
  expect_derivative("d2X/dt2",
                    [&](double t) {
                      const PoseMotion s = trajectory(t0 + t);
                      return Vector(rig.rest_shape_jacobian(s.p) * s.velocity);
                    },
                    rig.rest_shape_acceleration(m));
  // The reduced route: X is linear in the bone transforms and correction weights.
  Vector via_bones = Vector::Zero(3 * rig.num_vertices());
  const Matrix bone_acc = rig.bone_accelerations(m);
  for (int b = 0; b < rig.num_bones(); ++b) via_bones += rig.skinning_basis(b) * bone_acc.col(b);
  const Vector weight_acc = rig.weight_accelerations(m);
  for (int i = 0; i < weight_acc.size(); ++i) {
    const Matrix& d = rig.corrections()[static_cast<std::size_t>(i)].displacement;
    for (int v = 0; v < d.rows(); ++v) via_bones.segment<3>(3 * v) += weight_acc[i] * d.row(v).transpose();
  }
  EXPECT_LT((via_bones - rig.rest_shape_acceleration(m)).norm(), 1e-12 * rig.rest_shape_acceleration(m).norm());
  // and the skinning map reproduces X itself.
  Vector skinned = Vector::Zero(3 * rig.num_vertices());
  const BoneTransforms tr = rig.bone_transforms(m.p, false);
  for (int b = 0; b < rig.num_bones(); ++b) skinned += rig.skinning_basis(b) * vec12(tr.transform[b]);
  const PoseWeights pw = rig.pose_weights(m.p, false);
  for (int i = 0; i < pw.w.size(); ++i) {
    const Matrix& d = rig.corrections()[static_cast<std::size_t>(i)].displacement;
    for (int v = 0; v < d.rows(); ++v) skinned.segment<3>(3 * v) += pw.w[i] * d.row(v).transpose();
  }
  EXPECT_LT((skinned - rig.rest_shape(m.p)).norm(), 1e-12 * skinned.norm());
}

TEST(RigDerivatives, PoseWeightsInterpolateAndHaveExactDerivatives) {
  const std::vector<Vector> poses = {Vector::Zero(3), Vector::Ones(3), Vector::Unit(3, 0), -Vector::Unit(3, 2)};
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const PoseWeights w = normalized_pose_weights(poses, poses[i], false);
    EXPECT_LT((w.w - Vector::Unit(4, static_cast<int>(i))).norm(), 1e-15);
  }
  const Vector p = Vector::Random(3), dp = Vector::Random(3), a = Vector::Random(3);
  const PoseWeights w = normalized_pose_weights(poses, p, true);
  EXPECT_NEAR(w.w.sum(), 1.0, 1e-14);
  expect_derivative("dw/dp", [&](double t) { return normalized_pose_weights(poses, p + t * dp, false).w; },
                    w.gradient * dp);
  Vector second(4);
  for (int i = 0; i < 4; ++i) second[i] = a.dot(w.hessian[static_cast<std::size_t>(i)] * dp);
  expect_derivative("d2w/dp2",
                    [&](double t) { return Vector(normalized_pose_weights(poses, p + t * dp, false).gradient * a); },
                    second);
}

TEST(RigInput, RejectsBadRigs) {
  const Rig rig = chain_rig(1);
  Matrix bad_weights = rig.weights();
  bad_weights(2, 0) += 0.1;
  EXPECT_THROW(Rig(rig.bones(), rig.rest_positions(), bad_weights), std::invalid_argument);
  std::vector<Bone> bones = rig.bones();
  bones[1].parent = 2;
  EXPECT_THROW(Rig(bones, rig.rest_positions(), rig.weights()), std::invalid_argument);
  bones = rig.bones();
  bones[0].dofs[0].axis = Eigen::Vector3d(1, 1, 0);
  EXPECT_THROW(Rig(bones, rig.rest_positions(), rig.weights()), std::invalid_argument);
  EXPECT_THROW(PoseTrajectory({0.0, 0.0}, {Vector::Zero(2), Vector::Zero(2)}), std::invalid_argument);
}

SparseMatrix small_mass(Mesh& mesh) {
  mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 4, 2, 2);
  return mass_matrix(mesh, Vector::Constant(mesh.num_elements(), 1000.0), MassLumping::consistent);
}

TEST(PoseSpaceBasis, ProcrustesRecoversAKnownRotationToRoundOff) {
  Mesh mesh;
  const SparseMatrix mass = small_mass(mesh);
  const Matrix u0 = mass_orthonormal_basis(Matrix::Random(mass.rows(), 8), mass);
  // A random orthogonal matrix: the eigenvectors of a random symmetric one.
  const Matrix s = Matrix::Random(8, 8);
  Vector unused;
  Matrix q;
  symmetric_eigen<Eigen::Dynamic>(s + s.transpose(), unused, q);
  const Matrix u1 = u0 * q.transpose();
  const Matrix r = procrustes_rotation(u1, u0, mass);
  EXPECT_LT((r - q).norm(), 1e-12);
  EXPECT_LT((u1 * r - u0).norm(), 1e-12 * u0.norm());
  // A sign flip and a column swap (what an eigen solver does at another pose) are undone too.
  Matrix u2 = u0;
  u2.col(0) *= -1.0;
  u2.col(1).swap(u2.col(2));
  EXPECT_LT((u2 * procrustes_rotation(u2, u0, mass) - u0).norm(), 1e-12 * u0.norm());
}

TEST(PoseSpaceBasis, BlendEqualsTheAlignedBasisAtExamplePosesAndStaysOrthonormal) {
  Mesh mesh;
  const SparseMatrix mass = small_mass(mesh);
  std::vector<Matrix> bases;
  for (int i = 0; i < 3; ++i) bases.push_back(mass_orthonormal_basis(Matrix::Random(mass.rows(), 6), mass));
  const PoseSpaceBasis basis(bases, mass);
  for (int i = 0; i < 3; ++i) {
    const Matrix u = basis.blend(Vector::Unit(3, i));
    EXPECT_LT((u - basis.aligned(i)).norm(), 1e-12 * u.norm());
    EXPECT_LT((u - bases[static_cast<std::size_t>(i)] * basis.rotation(i)).norm(), 1e-12 * u.norm());
  }
  const Matrix u = basis.blend(Eigen::Vector3d(0.2, 0.5, 0.3));
  EXPECT_LT((u.transpose() * mass * u - Matrix::Identity(6, 6)).norm(), 1e-12);
}

// M^{-1/2} = V D^{-1/2} V^T from M = V D V^T (M symmetric positive definite).
Matrix inverse_square_root(const Matrix& m) {
  Vector d;
  Matrix v;
  symmetric_eigen<Eigen::Dynamic>(m, d, v);
  return v * d.cwiseInverse().cwiseSqrt().asDiagonal() * v.transpose();
}

// The finite eigenvalues of the Lagrange pencil [K C^T; C 0] x = lambda [M 0; 0 0] x, ascending
// (the stationary values of phi^T K phi / phi^T M phi on C phi = 0). With phi = M^{-1/2} psi the
// pencil becomes A psi = lambda psi + B^T mu, B psi = 0 (A = M^{-1/2} K M^{-1/2},
// B = C M^{-1/2}); with Q an orthonormal basis of range(B^T) and P = I - Q Q^T, the eigenpairs of
// P A P on range(P) are those of the constrained problem, and range(B^T) adds m zeros. K is
// positive definite here (a clamped block), so the m lowest eigenvalues of P A P are those zeros.
// A dense reference that shares nothing with the null-space QR and ARPACK route under test.
std::vector<double> lagrange_pencil_eigenvalues(const Matrix& k, const Matrix& m, const Matrix& c) {
  const Matrix m_half = inverse_square_root(m);
  const Matrix a = m_half * k * m_half;
  Matrix q = (c * m_half).transpose();
  for (int j = 0; j < q.cols(); ++j) {  // Gram-Schmidt, twice for round-off
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i < j; ++i) q.col(j) -= q.col(i).dot(q.col(j)) * q.col(i);
    q.col(j).normalize();
  }
  const Matrix p = Matrix::Identity(a.rows(), a.cols()) - q * q.transpose();
  const Matrix pap = p * a * p;
  const Vector values = symmetric_eigenvalues(Matrix(0.5 * (pap + pap.transpose())));
  const int dropped = static_cast<int>(c.rows());
  EXPECT_LT(std::abs(values[dropped - 1]), 1e-10 * values[dropped]) << "range(B^T) should hold the lowest (zero) eigenvalues";
  std::vector<double> finite(values.data() + dropped, values.data() + values.size());
  return finite;
}

// K phi = lambda M phi, C phi = 0 on a small clamped block against the dense Lagrange pencil
// (above), and Cauchy interlacing with the unconstrained eigenvalues (those of M^{-1/2} K M^{-1/2}).
TEST(ConstrainedModes, MatchDenseLagrangeSolveAndInterlace) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 4, 2, 2);
  const int ne = mesh.num_elements();
  const ElasticTerm<3> term(mesh, make_material<3>(MaterialKind::linear), 0, ne);
  Vector params(2 * ne);
  params << Vector::Constant(ne, 1e4), Vector::Constant(ne, 0.3);
  Vector x(3 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) x.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
  const Matrix k_full = Matrix(term.hessian(x, params, HessianMode::exact));
  const Matrix m_full = Matrix(mass_matrix(mesh, Vector::Constant(ne, 10.0), MassLumping::consistent));
  std::vector<int> free;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.rest_positions(v, 0) > 1e-9)
      for (int c = 0; c < 3; ++c) free.push_back(3 * v + c);
  const int n = static_cast<int>(free.size());
  Matrix k(n, n), m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) k(i, j) = k_full(free[i], free[j]), m(i, j) = m_full(free[i], free[j]);
  // Four contact-like constraints: normal displacements of vertex pairs tied.
  Matrix c = Matrix::Zero(4, n);
  for (int r = 0; r < 4; ++r) {
    const Eigen::Vector3d normal = Eigen::Vector3d::Random().normalized();
    c.block<1, 3>(r, 3 * (2 * r)) = normal.transpose();
    c.block<1, 3>(r, 3 * (2 * r + 7)) = -normal.transpose();
  }
  const int count = 8;
  GeneralizedEigenOptions eigen;
  eigen.dense_threshold = 0;  // ARPACK, as on a real mesh
  const ConstrainedModes modes = constrained_modes(k.sparseView(), m.sparseView(), c, count, eigen);
  EXPECT_FALSE(modes.solve.dense);
  EXPECT_EQ(modes.constraint_rank, 4);
  EXPECT_LT((c * modes.modes).norm(), 1e-10 * modes.modes.norm());
  EXPECT_LT((modes.modes.transpose() * m * modes.modes - Matrix::Identity(count, count)).norm(), 1e-10);

  const std::vector<double> finite = lagrange_pencil_eigenvalues(k, m, c);
  ASSERT_EQ(static_cast<int>(finite.size()), n - 4);
  const Vector free_values = symmetric_eigenvalues(Matrix(inverse_square_root(m) * k * inverse_square_root(m)));
  for (int i = 0; i < count; ++i) {
    EXPECT_NEAR(modes.eigenvalues[i], finite[static_cast<std::size_t>(i)], 1e-8 * finite[static_cast<std::size_t>(i)]);
    EXPECT_GE(modes.eigenvalues[i], free_values[i] * (1 - 1e-10));
    EXPECT_LE(modes.eigenvalues[i], free_values[i + 4] * (1 + 1e-10));
  }
  // The constraints matter: the unconstrained spectrum differs from the constrained one.
  EXPECT_GT(std::abs(modes.eigenvalues[0] - free_values[0]), 1e-3 * free_values[0]);
}

}  // namespace
}  // namespace tailor::rig::rig_test
