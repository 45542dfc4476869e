// Domain-decomposed (Craig-Bampton) and overlapping-domain reduced bases
// (domain_partition.hpp, domain_decomposition.hpp, overlapping_domains.hpp, local_reduced_stvk.hpp),
// and the local bases and the Krylov order as choices of inverse.design.reduction (the reduced
// design loop, problems/fem/reduced_design.hpp): Taylor tests, the reduced design against the
// full-space solve, and the keys' checks.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/reduction/domain_decomposition.hpp"
#include "forward/reduction/domain_partition.hpp"
#include "forward/reduction/free_space.hpp"
#include "forward/reduction/free_stiffness_factor.hpp"
#include "forward/reduction/local_reduced_stvk.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/overlapping_domains.hpp"
#include "reduction_fixtures.hpp"
#include "../../problems/reduced_design/small_handle_scene.hpp"
#include "../../support/temp_folder.hpp"
#include "adjoint/taylor_test.hpp"
#include "problems/fem/reduced_design.hpp"

namespace tailor::domain_reduction_test {
namespace {

using namespace tailor::testing;

ElasticBody cantilever(MaterialKind kind) {
  return elastic_body(Eigen::Vector2d(4, 1), Eigen::Vector2i(16, 4), kind, true, 1000.0, 0.3, 1.0);
}

// A downward load on the vertices of the free end x = 4.
Vector tip_load(const ElasticBody& body) {
  Vector f = Vector::Zero(body.rest.size());
  for (int v = 0; v < body.mesh.num_vertices(); ++v)
    if (body.mesh.rest_positions(v, 0) > 4 - 1e-9) f[2 * v + 1] = -1.0;
  return f;
}

// Linear Galerkin static solve in span(V): V (V^T K V)^{-1} V^T f, and the full one K^{-1} f.
Vector reduced_linear_solve(const ElasticBody& body, const Matrix& basis, const Vector& f) {
  Matrix kv(basis.rows(), basis.cols());
  for (Eigen::Index c = 0; c < basis.cols(); ++c) kv.col(c) = body.model->hessian_times(body.rest, body.p, basis.col(c));
  const Matrix kr = basis.transpose() * kv;
  return basis * kr.ldlt().solve(basis.transpose() * f);
}
Vector full_linear_solve(const ElasticBody& body, const Vector& f) {
  return FreeStiffnessFactor(*body.model, body.rest, body.p).solve(f);
}

TEST(DomainPartition, MetisGivesNonEmptyConnectedSizedDomains) {
  const ElasticBody body = elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(8, 2, 2), MaterialKind::linear, true);
  const Eigen::VectorXi domains = partition_elements(body.mesh, 4);
  ASSERT_EQ(domains.size(), body.mesh.num_elements());
  EXPECT_EQ(domain_count(domains), 4);
  for (int d = 0; d < 4; ++d) {
    const int count = static_cast<int>((domains.array() == d).count());
    EXPECT_GT(count, body.mesh.num_elements() / 8) << d;  // balanced within a factor 2
  }
  EXPECT_EQ(partition_elements(body.mesh, 4), domains);  // deterministic
  EXPECT_EQ(partition_elements(body.mesh, 1), Eigen::VectorXi::Zero(body.mesh.num_elements()));
  EXPECT_THROW(partition_elements(body.mesh, 0), std::invalid_argument);
  Mesh tagged = body.mesh;
  tagged.element_regions = Eigen::VectorXi::Constant(tagged.num_elements(), 7);
  tagged.element_regions.head(10).setConstant(3);
  const Eigen::VectorXi from_regions = domains_from_regions(tagged);
  EXPECT_EQ(from_regions[0], 0);
  EXPECT_EQ(from_regions[20], 1);
}

// Craig-Bampton with every interface DOF and the interior load responses contains the exact
// linear static solution (u_i = K_ii^-1 f_i + Psi u_b), so the Galerkin solve equals full FEM
// to round-off; without the load responses it does not (the check can fail).
TEST(DomainDecomposition, AllBoundaryModesGiveTheFullStaticSolve) {
  const ElasticBody body = cantilever(MaterialKind::linear);
  const Eigen::VectorXi domains = partition_elements(body.mesh, 3);
  const Vector f = tip_load(body);
  DomainDecompositionOptions options;
  options.fixed_interface_modes = 2;
  options.loads = f;
  const DomainDecomposition dd = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass, domains,
                                                      options);
  EXPECT_EQ(dd.boundary_driven_columns, static_cast<int>(dd.interface_dofs.size()));
  const Vector full = full_linear_solve(body, f);
  const double error = (reduced_linear_solve(body, dd.basis, f) - full).norm() / full.norm();
  std::printf("all %zu interface DOFs + load responses (%d columns): relative error %.2e\n", dd.interface_dofs.size(),
              static_cast<int>(dd.basis.cols()), error);
  EXPECT_LT(error, 1e-10);
  options.loads = Matrix();
  const DomainDecomposition without = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass,
                                                           domains, options);
  EXPECT_GT((reduced_linear_solve(body, without.basis, f) - full).norm(), 1e-4 * full.norm());
}

// The interface jump is zero: the interface DOFs are shared, every local column vanishes there
// exactly, and the boundary-driven columns are the only ones moving the interface. The basis is
// M-orthonormal and local columns keep to their domain's interior.
TEST(DomainDecomposition, LocalColumnsVanishOnTheInterface) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  const Eigen::VectorXi domains = partition_elements(body.mesh, 3);
  DomainDecompositionOptions options;
  options.fixed_interface_modes = 3;
  options.derivative_modes = 2;
  options.boundary_derivative_modes = 2;
  options.interface_modes = 4;
  const DomainDecomposition dd = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass, domains,
                                                      options);
  ASSERT_EQ(dd.basis.cols(), 3 * (3 + 3 + 3) + 4);
  EXPECT_LT((dd.basis.transpose() * (body.mass * dd.basis) - Matrix::Identity(dd.basis.cols(), dd.basis.cols()))
                .cwiseAbs()
                .maxCoeff(),
            1e-10);
  for (Eigen::Index c = 0; c < dd.basis.cols(); ++c) {
    const int d = dd.column_domain[static_cast<std::size_t>(c)];
    if (d < 0) continue;
    Vector outside = dd.basis.col(c);
    for (int dof : dd.interior_dofs[static_cast<std::size_t>(d)]) outside[dof] = 0.0;
    EXPECT_EQ(outside.cwiseAbs().maxCoeff(), 0.0) << "column " << c << " of domain " << d;
  }
  double driven = 0.0;
  for (Eigen::Index c = 0; c < dd.basis.cols(); ++c)
    if (dd.column_domain[static_cast<std::size_t>(c)] < 0)
      for (int dof : dd.interface_dofs) driven = std::max(driven, std::abs(dd.basis(dof, c)));
  EXPECT_GT(driven, 0.0);
}

// With the interface modes fixed, adding fixed-interface modes lowers the static error.
TEST(DomainDecomposition, ErrorFallsAsLocalModesAreAdded) {
  const ElasticBody body = cantilever(MaterialKind::linear);
  const Eigen::VectorXi domains = partition_elements(body.mesh, 3);
  const Vector f = tip_load(body);
  const Vector full = full_linear_solve(body, f);
  double previous = 1e300;
  for (int modes : {1, 2, 4, 8, 16}) {
    DomainDecompositionOptions options;
    options.fixed_interface_modes = modes;
    options.interface_modes = 6;
    const DomainDecomposition dd = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass,
                                                        domains, options);
    const double error = (reduced_linear_solve(body, dd.basis, f) - full).norm() / full.norm();
    std::printf("%2d fixed-interface modes per domain (%d columns): relative static error %.3e\n", modes,
                static_cast<int>(dd.basis.cols()), error);
    EXPECT_LT(error, previous);
    previous = error;
  }
  EXPECT_LT(previous, 1e-2);
}

// One domain: no interface, and the basis spans the global modes and modal derivatives.
TEST(DomainDecomposition, OneDomainReproducesTheGlobalReduction) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  DomainDecompositionOptions options;
  options.fixed_interface_modes = 4;
  options.derivative_modes = 3;
  const DomainDecomposition dd = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass,
                                                      Eigen::VectorXi::Zero(body.mesh.num_elements()), options);
  EXPECT_TRUE(dd.interface_dofs.empty());
  ModalAnalysisOptions modal;
  modal.count = 4;
  const Matrix modes = modal_analysis(*body.model, 2, body.rest, body.p, body.mass, modal).modes;
  Matrix global(modes.rows(), 4 + 6);
  global << modes, modal_derivatives(*body.model, body.rest, body.p, modes.leftCols(3));
  const Matrix basis = mass_orthonormal_basis(global, body.mass);
  ASSERT_EQ(dd.basis.cols(), basis.cols());
  // The M-orthogonal projections onto the two spans agree.
  const Matrix difference = dd.basis * (dd.basis.transpose() * (body.mass * global)) - global;
  EXPECT_LT(difference.norm(), 1e-8 * global.norm());
}

// The principal direction from the subspace iteration against the constrained equilibrium of
// the issue's KKT form solved densely, column by column, and a dense eigen solve of S^T M S.
TEST(OverlappingDomains, PrincipalDirectionMatchesADenseKktSolve) {
  const ElasticBody body = elastic_body(Eigen::Vector2d(3, 1), Eigen::Vector2i(9, 3), MaterialKind::linear, true);
  const Eigen::VectorXi domains = partition_elements(body.mesh, 3);
  OverlappingDomainOptions options;
  options.overlap_layers = 1;
  const OverlappingDomains od = overlapping_domains(*body.model, body.mesh, body.rest, body.p, body.mass, domains,
                                                    options);
  const std::vector<int> free = free_index_of_dofs(body.model->elimination());
  const Matrix K = Matrix(free_stiffness(*body.model, body.rest, body.p));
  const Matrix M = Matrix(free_mass(*body.model, body.mass));
  const int m = static_cast<int>(K.rows());
  for (int d = 0; d < 3; ++d) {
    std::vector<char> core(static_cast<std::size_t>(body.mesh.num_vertices()), 0), region = core;
    for (int e = 0; e < body.mesh.num_elements(); ++e)
      if (domains[e] == d)
        for (int a = 0; a < 3; ++a) core[static_cast<std::size_t>(body.mesh.elements(e, a))] = 1;
    for (int v : od.region_vertices[static_cast<std::size_t>(d)]) region[static_cast<std::size_t>(v)] = 1;
    std::vector<int> s, held;
    for (int dof = 0; dof < body.model->num_dofs(); ++dof) {
      const int f = free[static_cast<std::size_t>(dof)];
      if (f < 0) continue;
      if (core[static_cast<std::size_t>(dof / 2)]) s.push_back(f);
      if (!region[static_cast<std::size_t>(dof / 2)]) held.push_back(f);
    }
    const int ns = static_cast<int>(s.size()), nc = static_cast<int>(held.size());
    Matrix C = Matrix::Zero(nc, m);
    for (int i = 0; i < nc; ++i) C(i, held[static_cast<std::size_t>(i)]) = 1.0;
    Matrix kkt = Matrix::Zero(m + nc, m + nc);
    kkt << K, C.transpose(), C, Matrix::Zero(nc, nc);
    Matrix rhs = Matrix::Zero(m + nc, ns);
    for (int i = 0; i < ns; ++i) rhs(s[static_cast<std::size_t>(i)], i) = 1.0;
    const Matrix S = kkt.partialPivLu().solve(rhs).topRows(m);
    Vector dense_values;
    Matrix dense_vectors;
    symmetric_eigen<Eigen::Dynamic>(Matrix(S.transpose() * M * S), dense_values, dense_vectors);  // ascending
    const Vector p_dense = dense_vectors.col(ns - 1);
    Vector p_iter(ns);
    const Vector p_full = body.model->elimination().reduce(od.principal_forces[static_cast<std::size_t>(d)]);
    for (int i = 0; i < ns; ++i) p_iter[i] = p_full[s[static_cast<std::size_t>(i)]];
    EXPECT_NEAR(std::abs(p_iter.dot(p_dense)), 1.0, 1e-9) << d;
    EXPECT_NEAR(od.principal_values[d], dense_values[ns - 1], 1e-9 * dense_values[ns - 1]) << d;
    EXPECT_GT(dense_values[ns - 1], 1.5 * dense_values[ns - 2]);  // a well-separated top pair
  }
}

// The weights are a partition of unity, each vanishes outside its grown region, and the blended
// basis contains the local basis it blends.
TEST(OverlappingDomains, WeightsArePartitionOfUnityAndTheBlendContainsTheLocalBasis) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  const Eigen::VectorXi domains = partition_elements(body.mesh, 4);
  const OverlappingDomains od = overlapping_domains(*body.model, body.mesh, body.rest, body.p, body.mass, domains);
  EXPECT_LT((od.weights.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-14);
  EXPECT_GE(od.weights.minCoeff(), 0.0);
  for (int d = 0; d < 4; ++d) {
    std::vector<char> region(static_cast<std::size_t>(body.mesh.num_vertices()), 0);
    for (int v : od.region_vertices[static_cast<std::size_t>(d)]) region[static_cast<std::size_t>(v)] = 1;
    for (int v = 0; v < body.mesh.num_vertices(); ++v) {
      if (!region[static_cast<std::size_t>(v)]) {
        EXPECT_EQ(od.weights(v, d), 0.0);
      }
    }
  }
  ModalAnalysisOptions modal;
  modal.count = 3;
  const Matrix modes = modal_analysis(*body.model, 2, body.rest, body.p, body.mass, modal).modes;
  const Matrix blended = mass_orthonormal_basis(blended_basis(od.weights, modes, 2), body.mass, 1e-10);
  EXPECT_EQ(blended.cols(), 12);
  const Matrix difference = blended * (blended.transpose() * (body.mass * modes)) - modes;
  EXPECT_LT(difference.norm(), 1e-10 * modes.norm());
}

}  // namespace
}  // namespace tailor::domain_reduction_test

namespace tailor::domain_reduction_test {
namespace {

// The grouped polynomial equals one ReducedStvk over the whole basis (energy, force and
// stiffness at a random q), with several groups for a domain-decomposed basis.
TEST(LocalReducedStvk, EqualsTheGlobalPolynomial) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  DomainDecompositionOptions options;
  options.fixed_interface_modes = 2;
  options.derivative_modes = 2;
  options.interface_modes = 3;
  const DomainDecomposition dd = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass,
                                                      partition_elements(body.mesh, 3), options);
  const LocalReducedStvk local(*body.model, body.mesh, body.p, dd.basis);
  const ReducedStvk global(*body.model, body.p, dd.basis);
  EXPECT_GE(local.groups(), 3);
  EXPECT_LT(local.largest_group(), dd.basis.cols());
  const Vector q = 0.3 * Vector::Random(dd.basis.cols());
  double e1 = 0, e2 = 0;
  Vector f1, f2;
  Matrix k1, k2;
  local.evaluate(q, &e1, &f1, &k1);
  global.evaluate(q, &e2, &f2, &k2);
  EXPECT_NEAR(e1, e2, 1e-11 * std::abs(e2));
  EXPECT_LT((f1 - f2).norm(), 1e-11 * f2.norm());
  EXPECT_LT((k1 - k2).norm(), 1e-11 * k2.norm());
}

// The same in 3D (the tet path of the grouped precomputation), where groups share the
// boundary-driven columns, and force or tangent alone as in a chord Newton step; another
// material is refused (the polynomial is exact for StVK only).
TEST(LocalReducedStvk, EqualsTheGlobalPolynomialIn3dAndRefusesOtherMaterials) {
  const ElasticBody body = elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(8, 2, 2), MaterialKind::stvk, true);
  DomainDecompositionOptions options;
  options.fixed_interface_modes = 3;
  options.derivative_modes = 1;
  options.interface_modes = 4;
  const DomainDecomposition dd = domain_decomposition(*body.model, body.mesh, body.rest, body.p, body.mass,
                                                      partition_elements(body.mesh, 2), options);
  const LocalReducedStvk local(*body.model, body.mesh, body.p, dd.basis, 1e-14 * dd.basis.cwiseAbs().maxCoeff());
  const ReducedStvk global(*body.model, body.p, dd.basis);
  EXPECT_GE(local.groups(), 2);
  EXPECT_LT(local.largest_group(), dd.basis.cols());
  const Vector q = 0.3 * Vector::Random(dd.basis.cols());
  Vector f1, f2;
  Matrix k1, k2;
  local.evaluate(q, nullptr, &f1, nullptr);
  local.evaluate(q, nullptr, nullptr, &k1);
  global.evaluate(q, nullptr, &f2, &k2);
  EXPECT_NEAR(local.energy(q), global.energy(q), 1e-11 * std::abs(global.energy(q)));
  EXPECT_LT((f1 - f2).norm(), 1e-11 * f2.norm());
  EXPECT_LT((k1 - k2).norm(), 1e-11 * k2.norm());
  const ElasticBody neo = elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(4, 1, 1), MaterialKind::neo_hookean, true);
  EXPECT_THROW(LocalReducedStvk(*neo.model, neo.mesh, neo.p, Matrix::Identity(neo.rest.size(), 3)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::domain_reduction_test

namespace tailor::local_basis_scene_test {
namespace {

const char* const kDomains = R"(, "basis": "domains", "domains": {"count": 3, "fixed_interface_modes": 4,
    "derivative_modes": 2, "interface_modes": 6})";
const char* const kOverlapping = R"(, "basis": "overlapping", "domains": {"count": 3, "overlap_layers": 1})";
const char* const kKrylov = R"(, "krylov_order": 3)";

TEST(LocalBasisScene, TaylorTestOfTheReducedFunctionalWithEachBasis) {
  for (const char* extra : {kDomains, kOverlapping, kKrylov}) {
    ReducedDesign design = build_reduced_design(small_handle_scene("stvk", "[0, 0, -0.1]", extra));
    std::srand(5);
    const Vector w = 0.2 * Vector::Random(design.num_design());
    const TaylorTestResult r = taylor_test(*design.functional, w);
    EXPECT_TRUE(r.passed()) << extra << "\n" << r.message << "\n" << r.table();
    EXPECT_NEAR(r.rate0, 1.0, 0.1) << extra;
    EXPECT_GE(r.rate1, 1.9) << extra;
  }
}

// A reachable target (the full-space tip displacement of a known design) is reached in reduced
// coordinates and, solved again in full space, within 1%.
// (The domain basis only: each run takes seconds; the overlapping basis passes the Taylor test above.)
TEST(LocalBasisScene, ReducedDesignWithADomainBasisMatchesTheFullSpaceSolve) {
  for (const char* extra : {kDomains}) {
    const ReducedDesign probe = build_reduced_design(small_handle_scene("stvk", "[0, 0, -0.1]", extra));
    Vector w_star = Vector::Zero(probe.num_design());
    w_star[0] = -0.5;
    w_star[1] = 0.1;
    const FullSpaceCheck truth = full_space_check(probe, w_star);
    ASSERT_TRUE(truth.converged) << truth.message;
    const int tip = probe.handles[0].vertices[0];
    const Vector u = truth.displacement.segment(3 * tip, 3);
    const std::string target =
        "[" + std::to_string(u[0]) + ", " + std::to_string(u[1]) + ", " + std::to_string(u[2]) + "]";
    ReducedDesign design = build_reduced_design(small_handle_scene("stvk", target, extra));
    const ReducedDesignRun run = run_reduced_design(design, testing::unique_temp_path("local_basis_scene").string());
    ASSERT_TRUE(run.full && run.full->converged);
    EXPECT_LT(run.reduced_errors[0], 1e-3) << extra;
    EXPECT_LT(run.full->handle_errors[0], 1e-2) << extra;
  }
}

TEST(LocalBasisScene, KeysAreChecked) {
  const auto fails_naming = [](const std::string& extra, const std::string& key) {
    try {
      parse_scene(small_handle_scene_text("stvk", "[0, 0, -0.1]", extra), "s.json", ".");
      ADD_FAILURE() << extra;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  fails_naming(R"(, "basis": "domains", "domains": {"cont": 3})", "inverse.design.reduction.domains");
  fails_naming(R"(, "domains": {"count": 3})", "inverse.design.reduction.domains");  // basis global
  fails_naming(R"(, "basis": "patches")", "inverse.design.reduction.basis");
  fails_naming(R"(, "krylov_order": 9)", "inverse.design.reduction.krylov_order");
  EXPECT_NO_THROW(parse_scene(small_handle_scene_text("stvk", "[0, 0, -0.1]", kDomains), "s.json", "."));
}

}  // namespace
}  // namespace tailor::local_basis_scene_test
