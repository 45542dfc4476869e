// Meshless pipeline cost against the point count, and the error against the node count
// (docs/meshless.md, "Bench"). Part 1: a unit ball given by N oriented points (Fibonacci
// spiral), node spacing h: seconds per precomputation stage (implicit surface with its checks,
// octree nodes and quadrature, MLS shape functions at the quadrature points, stiffness and mass
// assembly with the modal analysis of `modes` modes, warping operators at the nodes and at the N
// samples) and the median time of one warped modal frame (modal step + warped displacements)
// at the nodes only and at all N samples. Part 2: the cantilever 10 x 1 x 1 (E = 1000, nu = 0.3,
// end shear 1, linear material) against Timoshenko's deflection as the nodes are refined.
// Part 3: one full-space Newton iteration (assembly, factorization, solve, line search; median
// over the iterations of a solve) of a neo-Hookean 4 x 1 x 1 cantilever under an end shear, on
// a node lattice of spacing h (41 x 11 x 11 = 4,961 nodes at h = 0.1), against the tet FEM on
// the same lattice (6 tets per cell, the same vertices and DOFs), both through NewtonSolver; the
// meshless steps by CHOLMOD (direct), by CG with the kept factor (reuse) or by CG preconditioned
// with a fixed factor, the tets' rest Hessian (fem-pcg) or the meshless one (rest-pcg). The
// patches of parts 2 and 3 pass through cover_points (grown only where a point is not covered),
// from the lattice spacing or each node's k-th neighbour (--neighbours).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>


#include "bench_cli.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/fem/loads.hpp"
#include "forward/meshless/covering_patches.hpp"
#include "forward/meshless/essential_conditions.hpp"
#include "forward/meshless/implicit_surface.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "forward/meshless/modal_warping.hpp"
#include "forward/meshless/octree_sampling.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/solve/fixed_preconditioner_cg.hpp"
#include "forward/solve/newton.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor::bench::meshless_bench {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

OrientedPoints fibonacci_ball(int n) {
  OrientedPoints p;
  p.source = "fibonacci ball";
  p.positions.resize(n, 3);
  p.normals.resize(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    p.normals.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
    p.positions.row(i) = p.normals.row(i);
  }
  return p;
}

struct PointCountResult {
  int points = 0, nodes = 0, quadrature_points = 0;
  double volume_error = 0.0;
  double implicit = 0.0, octree = 0.0, shape_functions = 0.0, modes = 0.0, warping = 0.0, total = 0.0;
  double frame_nodes = 0.0, frame_samples = 0.0;
  double frame_nodes_cpu = 0.0, frame_samples_cpu = 0.0;  // process CPU time, robust on a shared machine
  double cpu_total = 0.0;  // process CPU seconds of the precomputation (the machine may be shared)
};

PointCountResult precompute(int n, double spacing, int mode_count, int frames) {
  PointCountResult r;
  r.points = n;
  const std::clock_t cpu = std::clock();
  auto t = Clock::now();
  auto surface = std::make_shared<ImplicitSurface>(fibonacci_ball(n));
  r.implicit = since(t);
  t = Clock::now();
  const OctreeSampling s = sample_shape(ImplicitSurface::shape(surface), OctreeSamplingOptions{spacing, 2, 2});
  r.octree = since(t);
  r.nodes = static_cast<int>(s.nodes.rows());
  r.quadrature_points = static_cast<int>(s.points.rows());
  r.volume_error = s.volume() / (4.0 / 3.0 * M_PI) - 1.0;
  t = Clock::now();
  auto mls = std::make_shared<MlsShapeFunctions>(s.nodes, s.spacing);
  auto quadrature = std::make_shared<MeshlessQuadrature>(build_meshless_quadrature(*mls, s.points, s.weights));
  r.shape_functions = since(t);
  t = Clock::now();
  const int nodes = r.nodes;
  Model model(3 * nodes);
  model.parameter_layout().add("youngs_modulus", nodes);
  model.parameter_layout().add("poisson_ratio", nodes);
  model.add(std::make_unique<MeshlessElasticTerm<3>>(quadrature, make_material<3>(MaterialKind::linear), 0, nodes));
  Vector p(2 * nodes);
  p.head(nodes).setConstant(1000.0);
  p.tail(nodes).setConstant(0.3);
  const Eigen::MatrixXd nt = s.nodes.transpose();
  const Vector rest = Eigen::Map<const Vector>(nt.data(), nt.size());
  ModalAnalysisOptions modal;
  modal.count = mode_count;
  const ModalAnalysis m = modal_analysis(model, 3, rest, p, meshless_mass_matrix(*quadrature, 1.0), modal);
  r.modes = since(t);
  t = Clock::now();
  ModalWarpingOperators at_nodes = modal_warping_operators(*mls, m.modes, s.nodes);
  ModalWarpingOperators at_samples = modal_warping_operators(*mls, m.modes, surface->points().positions);
  r.warping = since(t);
  r.total = r.implicit + r.octree + r.shape_functions + r.modes + r.warping;
  r.cpu_total = static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
  // Frames: a tip force on the first sample for the first half, then free vibration.
  for (int which = 0; which < 2; ++which) {
    WarpedModalSimulator sim(which == 0 ? at_nodes : at_samples, m.eigenvalues, ModalRayleighDamping{0.1, 1e-4}, 1.0 / 60.0);
    Eigen::VectorXd u;
    std::vector<double> times, cpu_times;
    const Eigen::Vector3d force(0, 0, -500.0);
    for (int k = 0; k < frames; ++k) {
      t = Clock::now();
      const std::clock_t c = std::clock();
      sim.step(k < frames / 2 ? sim.modal_force(0, force) : Eigen::VectorXd::Zero(sim.num_modes()));
      sim.displacements(u, true);
      cpu_times.push_back(static_cast<double>(std::clock() - c) / CLOCKS_PER_SEC);
      times.push_back(since(t));
    }
    (which == 0 ? r.frame_nodes : r.frame_samples) = median(times);
    (which == 0 ? r.frame_nodes_cpu : r.frame_samples_cpu) = median(cpu_times);
  }
  return r;
}

// ---- the cantilever against Timoshenko

// Per-node patches for the lattice nodes of `s`: the spacing from the octree (neighbours = 0) or
// from each node's neighbours-th nearest node (covering_patches.hpp), then grown by cover_points
// where a quadrature point fails the covering condition.
struct Patches {
  Eigen::VectorXd spacing;
  CoveringReport covering;
};

Patches size_patches(const OctreeSampling& s, const MlsOptions& mls, int neighbours) {
  Patches r;
  const Eigen::VectorXd initial = neighbours > 0 ? neighbour_spacing(s.nodes, neighbours) : s.spacing;
  r.spacing = cover_points(s.nodes, initial, s.points, mls, CoveringOptions{}, &r.covering);
  return r;
}

struct BeamResult {
  double spacing = 0.0;
  int nodes = 0, points_repaired = 0, nodes_enlarged = 0;
  double deflection = 0.0, error = 0.0, seconds = 0.0;
};

BeamResult cantilever(double h, double support_factor, int quadrature_order, int neighbours) {
  constexpr double L = 10.0, E = 1000.0, nu = 0.3;
  BeamResult r;
  r.spacing = h;
  const auto t = Clock::now();
  const OctreeSampling s =
      sample_shape(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(L, 1, 1)), OctreeSamplingOptions{h, quadrature_order, 0});
  MlsOptions mls_options;
  mls_options.support_factor = support_factor;
  const Patches patches = size_patches(s, mls_options, neighbours);
  r.points_repaired = patches.covering.points_repaired;
  r.nodes_enlarged = patches.covering.nodes_enlarged;
  auto mls = std::make_shared<MlsShapeFunctions>(s.nodes, patches.spacing, mls_options);
  auto quadrature = std::make_shared<MeshlessQuadrature>(build_meshless_quadrature(*mls, s.points, s.weights));
  const int n = static_cast<int>(s.nodes.rows());
  // End face: 2 x 2 Gauss points per cell face, traction (0, 0, -1).
  std::vector<double> gx, gw;
  gauss_legendre(2, gx, gw);
  const int cells = static_cast<int>(std::lround(1.0 / h));
  Eigen::MatrixXd points(4 * cells * cells, 3), densities(4 * cells * cells, 3);
  Eigen::VectorXd weights(4 * cells * cells);
  int k = 0;
  for (int ci = 0; ci < cells; ++ci)
    for (int cj = 0; cj < cells; ++cj)
      for (std::size_t a = 0; a < 2; ++a)
        for (std::size_t b = 0; b < 2; ++b, ++k) {
          points.row(k) << L, h * (ci + 0.5 * (1 + gx[a])), h * (cj + 0.5 * (1 + gx[b]));
          weights[k] = 0.25 * h * h * gw[a] * gw[b];
          densities.row(k) << 0, 0, -1;
        }
  const Vector f = meshless_point_forces(*mls, points, weights, densities);
  Model model(3 * n);
  model.parameter_layout().add("youngs_modulus", n);
  model.parameter_layout().add("poisson_ratio", n);
  model.add(std::make_unique<MeshlessElasticTerm<3>>(quadrature, make_material<3>(MaterialKind::linear), 0, n));
  model.add(std::make_unique<ExternalForceTerm>(f));
  std::vector<int> clamped;
  for (int a = 0; a < n; ++a)
    if (s.nodes(a, 0) < 1e-9) clamped.push_back(a);
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(clamped.size()), 3);
  for (std::size_t i = 0; i < clamped.size(); ++i) targets.row(static_cast<Eigen::Index>(i)) = s.nodes.row(clamped[i]);
  model.set_elimination(mls_transformation(*mls, clamped, targets).elimination);
  const Eigen::MatrixXd nt = s.nodes.transpose();
  const Vector rest = Eigen::Map<const Vector>(nt.data(), nt.size());
  Vector p(2 * n);
  p.head(n).setConstant(E);
  p.tail(n).setConstant(nu);
  NewtonSolver solver(model);
  Vector y = model.elimination().restrict_state(rest);
  solver.solve(p, y);
  const Vector x = model.elimination().expand(y);
  const double I = 1.0 / 12.0, G = E / (2 * (1 + nu));
  const double exact = std::pow(L, 3) / (3 * E * I) + L / (5.0 / 6.0 * G);
  r.nodes = n;
  r.deflection = f.dot(x - rest);
  r.error = std::abs(r.deflection - exact) / exact;
  r.seconds = since(t);
  return r;
}

// ---- one Newton iteration, meshless against FEM at the same DOFs

struct NewtonRow {
  std::string method;
  std::string solver = "direct";  // meshless: direct, reuse, fem-pcg, rest-pcg (see run())
  int neighbours = 0, points_repaired = 0, nodes_enlarged = 0, cg_iterations = 0;
  double spacing = 0.0, support_factor = 0.0;  // support factor: meshless only
  int nodes = 0, dofs = 0, iterations = 0;
  long hessian_entries = 0;  // stored upper-triangle entries of the reduced Hessian
  double factor_nonzeros = 0.0, factor_flops = 0.0;  // of the Cholesky factor L (CHOLMOD's ordering)
  long basis_nonzeros = 0, longest_basis_row = 0;     // of the elimination's S (x = x0 + S y)
  std::pair<double, double> amd, metis, nesdis;        // (nnz(L), flops) under each ordering
  double model_build = 0.0;  // building the model: sampling, shape functions, quadrature, transformation
  double setup_cpu = 0.0;    // process CPU seconds of the solver construction
  double setup = 0.0;        // solver construction (pattern, symbolic analysis at the first factorization excluded)
  double iteration = 0.0, assembly = 0.0, factorization = 0.0, solve = 0.0, line_search = 0.0;  // medians per iteration
  double cpu_per_iteration = 0.0;  // process CPU seconds of the whole solve (analysis included) over its iterations
  double preconditioner_cpu = 0.0;  // fem-pcg, rest-pcg: process CPU seconds of assembling and factorizing P once
};

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

NewtonRow time_newton(const std::string& method, const Model& model, const Vector& p, const Vector& rest, int nodes,
                      const NewtonOptions& options = {}) {
  NewtonRow r;
  r.method = method;
  r.nodes = nodes;
  r.dofs = model.elimination().num_free();
  r.basis_nonzeros = static_cast<long>(model.elimination().basis().nonZeros());
  const std::vector<int>& row_begin = model.elimination().row_begin();
  for (std::size_t i = 0; i + 1 < row_begin.size(); ++i)
    r.longest_basis_row = std::max<long>(r.longest_basis_row, row_begin[i + 1] - row_begin[i]);
  auto t = Clock::now();
  const double cpu = cpu_seconds();
  NewtonSolver solver(model, options);
  r.setup = since(t);
  r.setup_cpu = cpu_seconds() - cpu;
  Vector y = model.elimination().restrict_state(rest);
  const double solve_cpu = cpu_seconds();
  const NewtonResult result = solver.solve(p, y);
  r.cpu_per_iteration = (cpu_seconds() - solve_cpu) / std::max(1, result.iterations);
  if (!result.converged()) throw std::runtime_error(method + ": Newton did not converge: " + result.message);
  const auto* external = dynamic_cast<const FixedPreconditionerCg*>(options.linear_solver.get());
  const SparseCholesky& factor = external ? external->preconditioner() : solver.factorization();
  r.factor_nonzeros = factor.factor_nonzeros();
  r.factor_flops = factor.factorization_flops();
  r.amd = estimate_factor_cost(solver.hessian(), FillOrdering::amd);
  r.metis = estimate_factor_cost(solver.hessian(), FillOrdering::metis);
  r.nesdis = estimate_factor_cost(solver.hessian(), FillOrdering::nesdis);
  std::vector<double> total, assembly, factorization, solve, line_search;
  for (const NewtonIteration& it : result.history) {
    total.push_back(it.assembly_seconds + it.factorization_seconds + it.solve_seconds + it.line_search_seconds);
    assembly.push_back(it.assembly_seconds);
    factorization.push_back(it.factorization_seconds);
    solve.push_back(it.solve_seconds);
    line_search.push_back(it.line_search_seconds);
    r.cg_iterations += it.cg_iterations;
  }
  r.iterations = result.iterations;
  r.iteration = median(total);
  r.assembly = median(assembly);
  r.factorization = median(factorization);
  r.solve = median(solve);
  r.line_search = median(line_search);
  r.hessian_entries = static_cast<long>(solver.hessian().nonZeros());
  return r;
}

// The P1-tet model on the node lattice of spacing h: the FEM row, and the fem-pcg preconditioner.
struct TetBar {
  std::unique_ptr<Model> model;
  Vector p, rest;
  Eigen::MatrixXd vertices;
};

TetBar tet_bar(double h, double load, double L, double E, double nu) {
  TetBar bar;
  const int along = static_cast<int>(std::lround(L / h)), across = static_cast<int>(std::lround(1.0 / h));
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(L, 1, 1), along, across, across);
  const int n = mesh.num_vertices(), m = mesh.num_elements();
  bar.model = std::make_unique<Model>(3 * n);
  Model& model = *bar.model;
  const int youngs = model.parameter_layout().add("youngs_modulus", m);
  const int poisson = model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), youngs, poisson));
  Vector f = Vector::Zero(3 * n);
  bar.rest.resize(3 * n);
  std::vector<int> fixed, end;
  for (int v = 0; v < n; ++v) {
    bar.rest.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
    if (mesh.rest_positions(v, 0) < 1e-9)
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
    if (mesh.rest_positions(v, 0) > L - 1e-9) end.push_back(v);
  }
  for (int v : end) f[3 * v + 2] = -load / static_cast<double>(end.size());
  model.add(std::make_unique<ExternalForceTerm>(f));
  model.set_elimination(Elimination::dirichlet(fixed, bar.rest));
  bar.p.resize(2 * m);
  bar.p.head(m).setConstant(E);
  bar.p.tail(m).setConstant(nu);
  bar.vertices = mesh.rest_positions;
  return bar;
}

// The upper triangle of a model's reduced Hessian at `rest` (exact mode).
SparseMatrix rest_hessian(const Model& model, const Vector& p, const Vector& rest) {
  NewtonSolver solver(model);
  solver.factorize_hessian(p, model.elimination().restrict_state(rest), HessianMode::exact);
  return solver.hessian();
}

// The tets' rest Hessian renumbered into the meshless free unknowns: both bars clamp the nodes
// at x = 0 and keep the others' components free in increasing DOF order, on the same lattice, so
// a vertex and a node at the same position carry the same three unknowns.
SparseMatrix fem_preconditioner(const TetBar& bar, const Eigen::MatrixXd& nodes, double h) {
  const SparseMatrix H = rest_hessian(*bar.model, bar.p, bar.rest);
  auto key = [h](const Eigen::Vector3d& X) {
    const long i = std::lround(X[0] / h), j = std::lround(X[1] / h), k = std::lround(X[2] / h);
    return (i * 100000 + j) * 100000 + k;
  };
  std::map<long, int> node_of;
  for (int a = 0; a < nodes.rows(); ++a) node_of[key(nodes.row(a).transpose())] = a;
  // Free index of each DOF: the clamped ones (x = 0) have none, the others count up.
  auto free_index = [](const Eigen::MatrixXd& X) {
    std::vector<int> index(static_cast<std::size_t>(3 * X.rows()), -1);
    int next = 0;
    for (int a = 0; a < X.rows(); ++a)
      if (X(a, 0) > 1e-9)
        for (int k = 0; k < 3; ++k) index[static_cast<std::size_t>(3 * a + k)] = next++;
    return index;
  };
  const std::vector<int> tet_free = free_index(bar.vertices), mls_free = free_index(nodes);
  Eigen::VectorXi to_mls(H.rows());
  for (int v = 0; v < bar.vertices.rows(); ++v) {
    const auto found = node_of.find(key(bar.vertices.row(v).transpose()));
    if (found == node_of.end()) throw std::runtime_error("fem_preconditioner: a tet vertex is no meshless node");
    for (int k = 0; k < 3; ++k) {
      const int t = tet_free[static_cast<std::size_t>(3 * v + k)];
      if (t >= 0) to_mls[t] = mls_free[static_cast<std::size_t>(3 * found->second + k)];
    }
  }
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation(to_mls);
  SparseMatrix upper(H.rows(), H.cols());
  upper.selfadjointView<Eigen::Upper>() = H.selfadjointView<Eigen::Upper>().twistedBy(permutation);
  upper.makeCompressed();
  return upper;
}

std::vector<NewtonRow> newton_comparison(double h, double load, const std::vector<double>& support_factors,
                                         const std::vector<std::string>& solvers, int neighbours, bool fem_reuse) {
  constexpr double L = 4.0, E = 1000.0, nu = 0.3;
  std::vector<NewtonRow> rows;
  const auto tet_wall = Clock::now();
  const TetBar bar = tet_bar(h, load, L, E, nu);
  const double tet_build = since(tet_wall);
  for (const double support_factor : support_factors) {
    const auto wall = Clock::now();
    const OctreeSampling s = sample_shape(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(L, 1, 1)), OctreeSamplingOptions{h, 2, 0});
    MlsOptions mls_options;
    mls_options.support_factor = support_factor;
    const Patches patches = size_patches(s, mls_options, neighbours);
    auto mls = std::make_shared<MlsShapeFunctions>(s.nodes, patches.spacing, mls_options);
    auto quadrature = std::make_shared<MeshlessQuadrature>(build_meshless_quadrature(*mls, s.points, s.weights));
    const int n = static_cast<int>(s.nodes.rows());
    // The end load as nodal forces of a uniform traction on x = L (one point per node of the face, weight h^2
    // inside: the consistent forces of the MLS fields are not needed for a timing).
    std::vector<int> clamped, end;
    for (int a = 0; a < n; ++a) {
      if (s.nodes(a, 0) < 1e-9) clamped.push_back(a);
      if (s.nodes(a, 0) > L - 1e-9) end.push_back(a);
    }
    Eigen::MatrixXd points(static_cast<Eigen::Index>(end.size()), 3), densities(points.rows(), 3);
    Eigen::VectorXd weights = Eigen::VectorXd::Constant(points.rows(), 1.0 / static_cast<double>(end.size()));
    for (std::size_t i = 0; i < end.size(); ++i) {
      points.row(static_cast<Eigen::Index>(i)) = s.nodes.row(end[i]);
      densities.row(static_cast<Eigen::Index>(i)) << 0, 0, -load;
    }
    Model model(3 * n);
    model.parameter_layout().add("youngs_modulus", n);
    model.parameter_layout().add("poisson_ratio", n);
    model.add(std::make_unique<MeshlessElasticTerm<3>>(quadrature, make_material<3>(MaterialKind::neo_hookean), 0, n));
    model.add(std::make_unique<ExternalForceTerm>(meshless_point_forces(*mls, points, weights, densities)));
    Eigen::MatrixXd targets(static_cast<Eigen::Index>(clamped.size()), 3);
    for (std::size_t i = 0; i < clamped.size(); ++i) targets.row(static_cast<Eigen::Index>(i)) = s.nodes.row(clamped[i]);
    model.set_elimination(mls_transformation(*mls, clamped, targets).elimination);
    const Eigen::MatrixXd nt = s.nodes.transpose();
    const Vector rest = Eigen::Map<const Vector>(nt.data(), nt.size());
    Vector p(2 * n);
    p.head(n).setConstant(E);
    p.tail(n).setConstant(nu);
    const double build = since(wall);
    for (const std::string& solver : solvers) {
      NewtonOptions options;
      double preconditioner_cpu = 0.0;
      if (solver == "reuse") {
        options.reuse_factorization = FactorReuse::on;
        options.reuse_max_cg_iterations = 100;
      } else if (solver == "fem-pcg" || solver == "rest-pcg") {
        const double cpu = cpu_seconds();
        const SparseMatrix P = solver == "fem-pcg" ? fem_preconditioner(bar, s.nodes, h) : rest_hessian(model, p, rest);
        options.linear_solver = std::make_shared<FixedPreconditionerCg>(P);
        preconditioner_cpu = cpu_seconds() - cpu;
      }
      rows.push_back(time_newton("meshless (MLS)", model, p, rest, n, options));
      NewtonRow& r = rows.back();
      r.solver = solver;
      r.support_factor = support_factor;
      r.model_build = build;
      r.neighbours = neighbours;
      r.points_repaired = patches.covering.points_repaired;
      r.nodes_enlarged = patches.covering.nodes_enlarged;
      r.preconditioner_cpu = preconditioner_cpu;
    }
  }
  NewtonOptions fem_options;
  if (fem_reuse) {
    fem_options.reuse_factorization = FactorReuse::on;
    fem_options.reuse_max_cg_iterations = 100;
  }
  rows.push_back(time_newton("P1 tets (FEM)", *bar.model, bar.p, bar.rest, static_cast<int>(bar.vertices.rows()), fem_options));
  rows.back().model_build = tet_build;
  rows.back().solver = fem_reuse ? "reuse" : "direct";
  for (NewtonRow& r : rows) r.spacing = h;
  return rows;
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> counts = {1000, 10000, 50000, 100000};
  double spacing = 0.2;
  int modes = 30, frames = 200;
  std::vector<int> per_unit = {2, 3, 4};
  std::vector<int> newton_cells = {10};
  double newton_load = 2.0;
  std::vector<std::string> support_text = {"2"};
  std::vector<std::string> solvers = {"direct"};
  int beam_quadrature = 3, neighbours = 0;
  std::vector<std::string> fem_solver = {"direct"};
  std::string out = "bench_meshless.json";
  bench::Cli cli("meshless_bench", "Meshless precomputation and warped modal frame time against the point count; error against the node count.");
  cli.integers("--points", counts, "point counts of the sampled ball", 100);
  cli.number("--spacing", spacing, "node spacing in the unit ball", 0.0);
  cli.integer("--modes", modes, "modes of the modal analysis and the warped frames", 1);
  cli.integer("--frames", frames, "timed warped modal frames (the median is reported)", 1);
  cli.integers("--beam-cells", per_unit, "cantilever: node cells per unit length (h = 1 / value); empty with 0", 0);
  cli.integers("--newton-cells", newton_cells,
               "Newton comparison: lattice cells per unit length, h = 1 / value (10: 4,961 nodes; 0 skips it)", 0);
  cli.names("--support-factors", support_text, "MLS support radius over the node spacing (Newton and cantilever rows)",
            "LIST", [](const std::string& v) {
              char* end = nullptr;
              const double f = std::strtod(v.c_str(), &end);
              return end != v.c_str() && *end == '\0' && f > 0.5 && f <= 4.0 ? std::string() : "a number in (0.5, 4]";
            });
  cli.number("--newton-load", newton_load, "Newton comparison: total end shear", 0.0);
  cli.names("--newton-solvers", solvers,
            "meshless Newton steps: direct (CHOLMOD, NewtonSolver's defaults), reuse (CG with the kept factor of an "
            "earlier iteration, FactorReuse::on), fem-pcg (CG preconditioned by the P1-tet rest Hessian on the same "
            "lattice), rest-pcg (CG preconditioned by the meshless rest Hessian)",
            "LIST", [](const std::string& v) {
              return v == "direct" || v == "reuse" || v == "fem-pcg" || v == "rest-pcg"
                         ? std::string()
                         : "one of direct, reuse, fem-pcg, rest-pcg";
            });
  cli.names("--fem-solver", fem_solver,
            "the FEM row's steps: direct (NewtonSolver's defaults) or reuse (CG with the kept factor, as the meshless reuse)",
            "NAME", [](const std::string& v) { return v == "direct" || v == "reuse" ? std::string() : "direct or reuse"; });
  cli.integer("--beam-quadrature", beam_quadrature, "cantilever: Gauss points per axis per cell", 1);
  cli.integer("--neighbours", neighbours,
              "patches from each node's k-th nearest node (0: the lattice spacing), then grown where a point is not "
              "covered (cantilever and Newton rows)",
              0);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::vector<double> support_factors;
  for (const std::string& v : support_text) support_factors.push_back(std::strtod(v.c_str(), nullptr));
  Json json = bench::report("meshless_bench");
  json["spacing"] = spacing;
  json["modes"] = modes;
  std::printf("%8s %6s %8s %9s %9s %9s %9s %9s %9s %9s %9s %11s %11s\n", "points", "nodes", "q-points", "vol.err",
              "implicit", "octree", "mls", "modes", "warp-ops", "total s", "cpu s", "frame nodes", "frame pts");
  std::printf("(frames: median wall ms, then median process CPU ms)\n");
  Json rows = Json::array();
  for (int n : counts) {
    const PointCountResult r = precompute(n, spacing, modes, frames);
    std::printf("%8d %6d %8d %9.2e %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f %6.3f/%6.3f %7.3f/%7.3f\n", r.points, r.nodes,
                r.quadrature_points, r.volume_error, r.implicit, r.octree, r.shape_functions, r.modes, r.warping, r.total,
                r.cpu_total, r.frame_nodes * 1e3, r.frame_nodes_cpu * 1e3, r.frame_samples * 1e3, r.frame_samples_cpu * 1e3);
    rows.push_back({{"points", r.points},
                    {"nodes", r.nodes},
                    {"quadrature_points", r.quadrature_points},
                    {"volume_error", r.volume_error},
                    {"seconds", {{"implicit_surface", r.implicit},
                                 {"octree", r.octree},
                                 {"shape_functions_and_quadrature", r.shape_functions},
                                 {"assembly_and_modes", r.modes},
                                 {"warping_operators", r.warping},
                                 {"total", r.total},
                                 {"total_cpu", r.cpu_total}}},
                    {"median_frame_seconds_nodes", r.frame_nodes},
                    {"median_frame_seconds_all_points", r.frame_samples},
                    {"median_frame_cpu_seconds_nodes", r.frame_nodes_cpu},
                    {"median_frame_cpu_seconds_all_points", r.frame_samples_cpu}});
  }
  json["point_counts"] = rows;
  Json beams = Json::array();
  if (!(per_unit.size() == 1 && per_unit[0] == 0))
    for (const double support_factor : support_factors) {
      std::printf("\ncantilever 10 x 1 x 1 against Timoshenko, support factor %g, %d Gauss points per axis, patches %s\n"
                  "%8s %6s %12s %10s %7s %9s %9s %9s\n",
                  support_factor, beam_quadrature, neighbours > 0 ? "from neighbours" : "from the lattice", "h", "nodes",
                  "deflection", "rel.err", "rate", "seconds", "repaired", "enlarged");
      std::vector<BeamResult> results;
      for (int c : per_unit) {
        if (c <= 0) continue;
        const BeamResult b = cantilever(1.0 / c, support_factor, beam_quadrature, neighbours);
        const double rate =
            results.empty() ? NAN : std::log(results.back().error / b.error) / std::log(results.back().spacing / b.spacing);
        std::printf("%8.4f %6d %12.6f %10.3e %7.2f %9.3f %9d %9d\n", b.spacing, b.nodes, b.deflection, b.error, rate,
                    b.seconds, b.points_repaired, b.nodes_enlarged);
        results.push_back(b);
        beams.push_back({{"support_factor", support_factor}, {"spacing", b.spacing}, {"nodes", b.nodes},
                         {"deflection", b.deflection}, {"relative_error", b.error},
                         {"rate", std::isfinite(rate) ? Json(rate) : Json()}, {"seconds", b.seconds},
                         {"quadrature_order", beam_quadrature}, {"neighbours", neighbours},
                         {"points_repaired", b.points_repaired}, {"nodes_enlarged", b.nodes_enlarged}});
      }
    }
  json["cantilever"] = beams;
  Json newton = Json::array();
  Json ratios = Json::array();
  for (const int cells : newton_cells) {
    if (cells <= 0) continue;
    const double h = 1.0 / cells;
    std::printf("\nNewton iteration, neo-Hookean cantilever 4 x 1 x 1, h = %g, end shear %g (medians per iteration, s)\n", h,
                newton_load);
    std::printf("%-16s %-8s %4s %6s %7s %10s %6s %10s %9s %4s %5s %8s %8s %9s %9s %9s %9s %9s %9s %9s\n", "method",
                "solver", "R/h", "nodes", "DOFs", "H entries", "H/row", "L entries", "L flops", "its", "CG", "build",
                "setup", "iteration", "assembly", "factor", "solve", "l.search", "cpu/it", "P cpu");
    const std::vector<NewtonRow> timed = newton_comparison(h, newton_load, support_factors, solvers, neighbours,
                                                           fem_solver.size() == 1 && fem_solver[0] == "reuse");
    const NewtonRow& fem = timed.back();
    for (const NewtonRow& r : timed) {
      std::printf("%-16s %-8s %4.3g %6d %7d %10ld %6.1f %10.3g %9.3g %4d %5d %8.3f %8.3f %9.4f %9.4f %9.4f %9.4f %9.4f "
                  "%9.4f %9.4f\n",
                  r.method.c_str(), r.solver.c_str(), r.support_factor, r.nodes, r.dofs, r.hessian_entries,
                  (2.0 * static_cast<double>(r.hessian_entries) - r.dofs) / r.dofs, r.factor_nonzeros, r.factor_flops,
                  r.iterations, r.cg_iterations, r.model_build, r.setup, r.iteration, r.assembly, r.factorization, r.solve,
                  r.line_search, r.cpu_per_iteration, r.preconditioner_cpu);
      newton.push_back({{"method", r.method}, {"solver", r.solver}, {"spacing", r.spacing}, {"support_factor", r.support_factor},
                        {"neighbours", r.neighbours}, {"points_repaired", r.points_repaired},
                        {"nodes_enlarged", r.nodes_enlarged}, {"cg_iterations", r.cg_iterations},
                        {"preconditioner_cpu_s", r.preconditioner_cpu},
                        {"nodes", r.nodes}, {"free_dofs", r.dofs}, {"hessian_entries", r.hessian_entries},
                        {"basis_nonzeros", r.basis_nonzeros}, {"longest_basis_row", r.longest_basis_row},
                        {"factor_nonzeros", r.factor_nonzeros},
                        {"orderings", {{"amd", {{"factor_nonzeros", r.amd.first}, {"flops", r.amd.second}}},
                                       {"metis", {{"factor_nonzeros", r.metis.first}, {"flops", r.metis.second}}},
                                       {"nesdis", {{"factor_nonzeros", r.nesdis.first}, {"flops", r.nesdis.second}}}}}, {"factorization_flops", r.factor_flops},
                        {"iterations", r.iterations}, {"model_build_s", r.model_build}, {"setup_s", r.setup},
                        {"setup_cpu_s", r.setup_cpu}, {"median_iteration_s", r.iteration},
                        {"median_assembly_s", r.assembly}, {"median_factorization_s", r.factorization},
                        {"median_solve_s", r.solve}, {"median_line_search_s", r.line_search},
                        {"cpu_per_iteration_s", r.cpu_per_iteration}, {"ratio_to_fem", r.iteration / fem.iteration},
                        {"cpu_ratio_to_fem", r.cpu_per_iteration / fem.cpu_per_iteration}});
    }
    std::printf("factorization flops by ordering (CHOLMOD's analysis): ");
    for (const NewtonRow& r : timed)
      std::printf("%s%s R/h %g: AMD %.3g, METIS %.3g, NESDIS %.3g", &r == timed.data() ? "" : "; ",
                  r.method.c_str(), r.support_factor, r.amd.second, r.metis.second, r.nesdis.second);
    std::printf("\n");
    for (std::size_t k = 0; k + 1 < timed.size(); ++k) {
      std::printf("meshless (R/h = %g, %s) / FEM per iteration: %.2f wall, %.2f CPU (goal: <= 3)\n",
                  timed[k].support_factor, timed[k].solver.c_str(), timed[k].iteration / fem.iteration,
                  timed[k].cpu_per_iteration / fem.cpu_per_iteration);
      ratios.push_back({{"spacing", h}, {"support_factor", timed[k].support_factor}, {"solver", timed[k].solver},
                        {"ratio", timed[k].iteration / fem.iteration},
                        {"cpu_ratio", timed[k].cpu_per_iteration / fem.cpu_per_iteration}});
    }
  }
  json["newton_ratio"] = ratios;
  json["newton"] = newton;
  return bench::write_report(out, json, "meshless_bench") ? 0 : 1;
}

}  // namespace tailor::bench::meshless_bench
