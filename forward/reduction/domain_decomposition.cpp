#include "forward/reduction/domain_decomposition.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/reduction/domain_partition.hpp"
#include "forward/reduction/free_space.hpp"
#include "forward/reduction/generalized_eigen.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/krylov_recurrence.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {
namespace {

// An interior block K_ii factorized (upper triangle).
struct InteriorFactor {
  SparseCholesky factor;
  void factorize(const SparseMatrix& k, int domain) {
    SparseMatrix upper = SparseMatrix(k.triangularView<Eigen::Upper>());
    upper.makeCompressed();
    const FactorizationResult f = factor.factorize(upper);
    if (!f.success || !f.positive_definite)
      throw std::runtime_error("domain_decomposition: the interior stiffness of domain " + std::to_string(domain) +
                               " is not positive definite: " + f.message);
  }
};

// Free-space index lists of every domain's interior and of the interface.
struct FreeSplit {
  std::vector<std::vector<int>> interior;
  std::vector<int> interface;
};

FreeSplit split_free_unknowns(const Mesh& mesh, const Eigen::VectorXi& element_domain, int domains,
                              const std::vector<int>& dof_to_free) {
  const int dim = mesh.dim();
  std::vector<int> vertex_domain(static_cast<std::size_t>(mesh.num_vertices()), -1);  // -2: on an interface
  for (int e = 0; e < mesh.num_elements(); ++e)
    for (int a = 0; a < mesh.elements.cols(); ++a) {
      int& v = vertex_domain[static_cast<std::size_t>(mesh.elements(e, a))];
      if (v == -1)
        v = element_domain[e];
      else if (v != element_domain[e])
        v = -2;
    }
  FreeSplit split;
  split.interior.resize(static_cast<std::size_t>(domains));
  for (int v = 0; v < mesh.num_vertices(); ++v)
    for (int k = 0; k < dim; ++k) {
      const int f = dof_to_free[static_cast<std::size_t>(dim * v + k)];
      const int d = vertex_domain[static_cast<std::size_t>(v)];
      if (f < 0 || d == -1) continue;
      if (d == -2)
        split.interface.push_back(f);
      else
        split.interior[static_cast<std::size_t>(d)].push_back(f);
    }
  return split;
}

Matrix rows_of(const Matrix& a, const std::vector<int>& rows) {
  Matrix out(static_cast<Eigen::Index>(rows.size()), a.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = a.row(rows[i]);
  return out;
}

}  // namespace

void PhaseClock::add(std::vector<PhaseTiming>& phases, const std::string& name) {
  const auto wall = std::chrono::steady_clock::now();
  const std::clock_t cpu = std::clock();
  auto it = std::find_if(phases.begin(), phases.end(), [&](const PhaseTiming& t) { return t.name == name; });
  if (it == phases.end()) it = phases.insert(phases.end(), PhaseTiming{name, 0.0, 0.0});
  it->wall_s += std::chrono::duration<double>(wall - wall_).count();
  it->cpu_s += static_cast<double>(cpu - cpu_) / CLOCKS_PER_SEC;
  wall_ = wall;
  cpu_ = cpu;
}

std::vector<int> free_index_of_dofs(const Elimination& elimination) {
  if (!elimination.is_selection())
    throw std::invalid_argument("domain-decomposed reduction needs Dirichlet constraints (a selection elimination)");
  const SparseMatrix& S = elimination.basis();
  std::vector<int> dof_to_free(static_cast<std::size_t>(S.rows()), -1);
  for (int c = 0; c < S.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(S, c); it; ++it) dof_to_free[static_cast<std::size_t>(it.row())] = c;
  return dof_to_free;
}

SparseMatrix sparse_block(const SparseMatrix& A, const std::vector<int>& rows, const std::vector<int>& cols) {
  std::vector<int> col_index(static_cast<std::size_t>(A.cols()), -1);
  for (std::size_t j = 0; j < cols.size(); ++j) col_index[static_cast<std::size_t>(cols[j])] = static_cast<int>(j);
  std::vector<Eigen::Triplet<double>> triplets;
  // Row-major traversal through the transpose keeps this O(nnz of the picked rows).
  const Eigen::SparseMatrix<double, Eigen::RowMajor> row_major(A);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(row_major, rows[i]); it; ++it) {
      const int j = col_index[static_cast<std::size_t>(it.col())];
      if (j >= 0) triplets.emplace_back(static_cast<int>(i), j, it.value());
    }
  SparseMatrix out(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
  out.setFromTriplets(triplets.begin(), triplets.end());
  return out;
}

DomainDecomposition domain_decomposition(const Model& model, const Mesh& mesh, const Vector& x, const Vector& p,
                                         const SparseMatrix& mass, const Eigen::VectorXi& element_domain,
                                         const DomainDecompositionOptions& options) {
  const auto begin = std::chrono::steady_clock::now();
  DomainDecomposition out;
  PhaseClock clock;
  const int n = model.num_dofs();
  if (n != mesh.dim() * mesh.num_vertices() || x.size() != n || mass.rows() != n || mass.cols() != n)
    throw std::invalid_argument("domain_decomposition: model, mesh, state and mass sizes differ");
  if (element_domain.size() != mesh.num_elements() || element_domain.size() == 0 || element_domain.minCoeff() < 0)
    throw std::invalid_argument("domain_decomposition: need one domain index >= 0 per element");
  if (options.fixed_interface_modes < 0 || options.interface_modes < 0 || options.derivative_modes < 0)
    throw std::invalid_argument("domain_decomposition: mode counts must be >= 0");
  if (options.loads.size() > 0 && options.loads.rows() != n)
    throw std::invalid_argument("domain_decomposition: loads need " + std::to_string(n) + " rows");
  const SparseMatrix& S = model.elimination().basis();
  const std::vector<int> dof_to_free = free_index_of_dofs(model.elimination());

  const int domains = domain_count(element_domain);
  const FreeSplit split = split_free_unknowns(mesh, element_domain, domains, dof_to_free);
  const SparseMatrix K = free_stiffness(model, x, p), M = free_mass(model, mass);
  clock.add(out.phases, "stiffness and mass");
  const Eigen::Index m = K.rows();
  double step = options.step;
  if (step == 0.0) step = 1e-3 * std::max(x.maxCoeff() - x.minCoeff(), 1e-300);

  // Interface excitations E (|B| x e).
  const std::vector<int>& B = split.interface;
  const int nb = static_cast<int>(B.size());
  Matrix excitations;
  if (nb > 0) {
    if (options.interface_modes == 0 || options.interface_modes >= nb) {
      excitations = Matrix::Identity(nb, nb);
    } else {
      // The interface traces of the lowest global modes and the modal derivatives of the
      // lowest k of them (k + k (k + 1) / 2 >= n), in that order, the first n independent ones.
      const int n_wanted = options.interface_modes;
      ModalAnalysisOptions modal;
      modal.count = std::min(n_wanted, static_cast<int>(m) - 1);
      const Matrix global = modal_analysis(model, mesh.dim(), x, p, mass, modal).modes;
      clock.add(out.phases, "interface excitations: global modes");
      int k = 1;
      while (k + k * (k + 1) / 2 < n_wanted) ++k;
      k = std::min<int>(k, static_cast<int>(global.cols()));
      const Matrix psi = modal_derivatives(model, x, p, global.leftCols(k));
      clock.add(out.phases, "interface excitations: global modal derivatives");
      Matrix candidates(n, global.cols() + psi.cols());
      candidates << global.leftCols(k), psi, global.rightCols(global.cols() - k);
      const Matrix ordered = mass_orthonormal_basis(candidates, mass, 1e-6);
      const Matrix ordered_free = S.transpose() * ordered.leftCols(std::min<Eigen::Index>(n_wanted, ordered.cols()));
      Matrix traces = rows_of(ordered_free, B);
      excitations = orthonormal_columns(traces, std::min<Eigen::Index>(traces.cols(), nb));
    }
    clock.add(out.phases, "interface excitations: traces");
  }
  Matrix driven = Matrix::Zero(m, excitations.cols());
  for (int i = 0; i < nb; ++i) driven.row(B[static_cast<std::size_t>(i)]) = excitations.row(i);
  const Matrix coupling = K * driven;  // K_ib u_b in the interior rows

  // Interior factors; the boundary-driven modes' interior parts.
  std::vector<std::unique_ptr<InteriorFactor>> factors(static_cast<std::size_t>(domains));
  for (int d = 0; d < domains; ++d) {
    const std::vector<int>& I = split.interior[static_cast<std::size_t>(d)];
    if (I.empty()) continue;
    factors[static_cast<std::size_t>(d)] = std::make_unique<InteriorFactor>();
    factors[static_cast<std::size_t>(d)]->factorize(sparse_block(K, I, I), d);
    clock.add(out.phases, "interior factorizations");
    if (driven.cols() > 0) {
      const Matrix response = -factors[static_cast<std::size_t>(d)]->factor.solve_columns(rows_of(coupling, I));
      for (std::size_t i = 0; i < I.size(); ++i) driven.row(I[i]) = response.row(static_cast<Eigen::Index>(i));
      clock.add(out.phases, "boundary-driven modes");
    }
  }
  // Force differentials of the lowest boundary-driven modes, -F_2[psi_a, psi_b] (free space).
  const int nbd = std::min<int>(options.boundary_derivative_modes, static_cast<int>(driven.cols()));
  Matrix driven_rhs(m, nbd * (nbd + 1) / 2);
  for (int a = 0, c = 0; a < nbd; ++a)
    for (int b = a; b < nbd; ++b, ++c)
      driven_rhs.col(c) = -(S.transpose() * force_derivative(model, x, p, {Vector(S * driven.col(a)),
                                                                          Vector(S * driven.col(b))}, step));
  clock.add(out.phases, "boundary-driven derivatives: force differentials");

  std::vector<Matrix> local(static_cast<std::size_t>(domains));
  const Matrix loads_free = options.loads.size() > 0 ? Matrix(S.transpose() * options.loads) : Matrix(m, 0);
  for (int d = 0; d < domains; ++d) {
    const std::vector<int>& I = split.interior[static_cast<std::size_t>(d)];
    const int ni = static_cast<int>(I.size());
    if (ni == 0) continue;
    InteriorFactor& factor = *factors[static_cast<std::size_t>(d)];
    const SparseMatrix kii = sparse_block(K, I, I);
    std::vector<Matrix> columns;  // interior-sized
    Matrix modes(ni, 0);
    const int count = std::min(options.fixed_interface_modes, ni - 1);
    if (count > 0) {
      const GeneralizedEigenResult eig = generalized_eigenpairs(kii, sparse_block(M, I, I), count);
      if (!eig.success)
        throw std::runtime_error("domain_decomposition: fixed-interface modes of domain " + std::to_string(d) + ": " +
                                 eig.message);
      modes = eig.eigenvectors;
      columns.push_back(modes);
      clock.add(out.phases, "fixed-interface modes");
    }
    const int r = std::min<int>(options.derivative_modes, static_cast<int>(modes.cols()));
    if (r > 0) {
      // Full-space modes for the Hessian products; the right-hand sides restricted to the interior.
      const auto full = [&](const Vector& interior) {
        Vector y = Vector::Zero(m);
        for (int i = 0; i < ni; ++i) y[I[static_cast<std::size_t>(i)]] = interior[i];
        return Vector(S * y);
      };
      std::vector<Vector> phi;
      for (int a = 0; a < r; ++a) phi.push_back(full(modes.col(a)));
      Matrix rhs(ni, r * (r + 1) / 2);
      for (int a = 0, c = 0; a < r; ++a)
        for (int b = a; b < r; ++b, ++c) {
          const Vector h = S.transpose() * force_derivative(model, x, p, {phi[a], phi[b]}, step);
          for (int i = 0; i < ni; ++i) rhs(i, c) = -h[I[static_cast<std::size_t>(i)]];
        }
      columns.push_back(factor.factor.solve_columns(rhs));
      clock.add(out.phases, "local modal derivatives");
    }
    if (nbd > 0) columns.push_back(factor.factor.solve_columns(rows_of(driven_rhs, I)));
    if (loads_free.cols() > 0) columns.push_back(factor.factor.solve_columns(rows_of(loads_free, I)));
    clock.add(out.phases, "boundary-driven derivatives and load responses: solves");
    Eigen::Index total = 0;
    for (const Matrix& c : columns) total += c.cols();
    Matrix& block = local[static_cast<std::size_t>(d)];
    block = Matrix::Zero(m, total);
    Eigen::Index at = 0;
    for (const Matrix& c : columns) {
      for (int i = 0; i < ni; ++i) block.row(I[static_cast<std::size_t>(i)]).segment(at, c.cols()) = c.row(i);
      at += c.cols();
    }
  }

  Eigen::Index total = driven.cols();
  for (const Matrix& b : local) total += b.cols();
  Matrix all(m, total);
  std::vector<int> source_domain;
  Eigen::Index at = 0;
  for (int d = 0; d < domains; ++d) {
    const Matrix& b = local[static_cast<std::size_t>(d)];
    all.middleCols(at, b.cols()) = b;
    at += b.cols();
    source_domain.insert(source_domain.end(), static_cast<std::size_t>(b.cols()), d);
  }
  all.rightCols(driven.cols()) = driven;
  source_domain.insert(source_domain.end(), static_cast<std::size_t>(driven.cols()), -1);

  clock.add(out.phases, "local columns");
  std::vector<int> kept;
  out.basis = mass_orthonormal_basis(Matrix(S * all), mass, options.drop_tolerance, &kept);
  clock.add(out.phases, "M-orthonormalization");
  for (int k : kept) {
    out.column_domain.push_back(source_domain[static_cast<std::size_t>(k)]);
    if (source_domain[static_cast<std::size_t>(k)] < 0) ++out.boundary_driven_columns;
  }
  std::vector<int> free_to_dof(static_cast<std::size_t>(m));
  for (int dof = 0; dof < n; ++dof)
    if (dof_to_free[static_cast<std::size_t>(dof)] >= 0) free_to_dof[static_cast<std::size_t>(dof_to_free[static_cast<std::size_t>(dof)])] = dof;
  for (const auto& I : split.interior) {
    out.interior_dofs.emplace_back();
    for (int f : I) out.interior_dofs.back().push_back(free_to_dof[static_cast<std::size_t>(f)]);
  }
  for (int f : B) out.interface_dofs.push_back(free_to_dof[static_cast<std::size_t>(f)]);
  out.domains = domains;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return out;
}

}  // namespace tailor
