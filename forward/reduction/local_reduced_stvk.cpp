#include "forward/reduction/local_reduced_stvk.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "forward/core/parallel_errors.hpp"
#include "forward/fem/elastic_term.hpp"

// The reference BLAS interface (OpenBLAS in this build, through CHOLMOD's dependency).
extern "C" void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
                       const double* a, const int* lda, const double* beta, double* c, const int* ldc);

namespace tailor {
namespace {

// What the precomputation reads of one element of an elastic term: rest shape gradients
// (row a: grad N_a), vertices, Lame parameters and rest volume.
struct ElementData {
  Matrix shape_gradients;
  std::vector<int> vertices;
  LameParameters lame{0.0, 0.0};
  double volume = 0.0;
};
template <int Dim>
ElementData element_data(const ElasticTerm<Dim>& term, const Vector& p, int k) {
  ElementData out;
  out.shape_gradients = term.shape_gradients(k);
  const auto& vertices = term.element_vertices(k);
  out.vertices.assign(vertices.data(), vertices.data() + vertices.size());
  out.lame = term.element_lame(p, k);
  out.volume = term.rest_volume(k);
  return out;
}

// Adds sum_e Y_e Y_e^T over the given elements of one elastic term to the lower triangle of
// gram ((r + P) x (r + P)), with Y_e the element's (r + P) x components columns of
// reduced_stvk.hpp: the linear strain rows L_e Lw and the pair rows N_e Lw / 2, Lw the Cholesky
// factor of the element's strain weights V_e W (Psi = 1/2 e^T W e over the independent strain
// components, off-diagonals counted twice). basis_t: the group's columns, transposed (r x
// num_dofs). Chunks of elements are filled in parallel (OpenMP) and added by one BLAS rank-k
// update each (dsyrk, which keeps OpenBLAS's threads): the update is O((r + P)^2) per element
// and dominates, the fill is O(r^2). One code for 2D and 3D (dim at run time) keeps its
// compile cost to one instantiation.
void add_group_elements(int dim, const std::function<ElementData(int)>& element, const Matrix& basis_t,
                        const std::vector<int>& elements, Matrix& gram) {
  constexpr int kChunk = 256;
  const int components = dim * (dim + 1) / 2, nodes = dim + 1;
  const int r = static_cast<int>(basis_t.rows()), pairs = r * (r + 1) / 2, width = r + pairs;
  std::vector<int> comp_a(static_cast<std::size_t>(components)), comp_b(comp_a);  // c <-> (a, b): diagonal first
  for (int c = 0, k = dim; c < dim; ++c) {
    comp_a[static_cast<std::size_t>(c)] = comp_b[static_cast<std::size_t>(c)] = c;
    for (int d = c + 1; d < dim; ++d, ++k) comp_a[static_cast<std::size_t>(k)] = c, comp_b[static_cast<std::size_t>(k)] = d;
  }
  Matrix y(width, components * kChunk);
  const int total = static_cast<int>(elements.size());
  for (int start = 0; start < total; start += kChunk) {
    const int count = std::min(kChunk, total - start);
    FirstError errors;  // element_lame refuses parameters out of range
#pragma omp parallel
    {
      Matrix g(dim * dim, r), outer(r, r), linear(r, components), quadratic(pairs, components);  // g: d(grad u)_ib / dq
      Matrix W(components, components);
#pragma omp for schedule(static)
      for (int e = 0; e < count; ++e) try {
        const ElementData data = element(elements[static_cast<std::size_t>(start + e)]);
        g.setZero();
        for (int a = 0; a < nodes; ++a)
          for (int i = 0; i < dim; ++i)
            for (int b = 0; b < dim; ++b)
              g.row(i + dim * b) += data.shape_gradients(a, b) *
                                    basis_t.col(dim * data.vertices[static_cast<std::size_t>(a)] + i).transpose();
        W.setZero();
        W.topLeftCorner(dim, dim).setConstant(data.lame.lambda);
        for (int c = 0; c < components; ++c) W(c, c) += (c < dim ? 2.0 : 4.0) * data.lame.mu;
        W *= data.volume;
        const Matrix Lw = W.llt().matrixL();
        for (int c = 0; c < components; ++c) {
          const int a = comp_a[static_cast<std::size_t>(c)], b = comp_b[static_cast<std::size_t>(c)];
          linear.col(c) = 0.5 * (g.row(a + dim * b) + g.row(b + dim * a)).transpose();
          // N_ab = sum_i (grad u)_ia (grad u)_ib = q^T outer q, packed on the pairs.
          outer.noalias() = g.row(dim * a).transpose() * g.row(dim * b);
          for (int i = 1; i < dim; ++i) outer.noalias() += g.row(i + dim * a).transpose() * g.row(i + dim * b);
          for (int s = 0, pair = 0; s < r; ++s) {
            quadratic(pair++, c) = outer(s, s);
            for (int t = s + 1; t < r; ++t) quadratic(pair++, c) = outer(s, t) + outer(t, s);
          }
        }
        y.block(0, components * e, r, components).noalias() = linear * Lw;
        y.block(r, components * e, pairs, components).noalias() = 0.5 * quadratic * Lw;
      } catch (...) {
        errors.capture(start + e);
      }
    }
    errors.rethrow();
    const int n = width, kk = components * count, ld = width;
    const double one = 1.0;
    dsyrk_("L", "N", &n, &kk, &one, y.data(), &ld, &one, gram.data(), &ld);
  }
}

}  // namespace

LocalReducedStvk::LocalReducedStvk(const Model& model, const Mesh& mesh, const Vector& p, const Matrix& basis,
                                   double zero_tolerance) {
  const auto begin = std::chrono::steady_clock::now();
  const std::clock_t cpu_begin = std::clock();
  const int dim = mesh.dim(), n = model.num_dofs();
  if (basis.rows() != n || n != dim * mesh.num_vertices())
    throw std::invalid_argument("LocalReducedStvk: basis, model and mesh sizes differ");
  r_ = static_cast<int>(basis.cols());
  if (r_ < 1) throw std::invalid_argument("LocalReducedStvk: empty basis");
  // Vertex signatures: the set of columns nonzero at the vertex, numbered.
  std::map<std::vector<int>, int> signature_index;
  std::vector<std::vector<int>> signatures;
  std::vector<int> vertex_signature(static_cast<std::size_t>(mesh.num_vertices()));
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    std::vector<int> columns;
    for (int c = 0; c < r_; ++c)
      if (basis.block(dim * v, c, dim, 1).cwiseAbs().maxCoeff() > zero_tolerance) columns.push_back(c);
    const auto [it, inserted] = signature_index.emplace(columns, static_cast<int>(signatures.size()));
    if (inserted) signatures.push_back(columns);
    vertex_signature[static_cast<std::size_t>(v)] = it->second;
  }
  // Element groups: the union of their vertices' signatures.
  std::map<std::vector<int>, int> element_key_group;  // sorted vertex signatures -> group
  std::map<std::vector<int>, int> columns_group;       // column set -> group
  std::vector<int> mesh_element_group(static_cast<std::size_t>(mesh.num_elements()));
  for (int e = 0; e < mesh.num_elements(); ++e) {
    std::vector<int> key;
    for (int a = 0; a < mesh.elements.cols(); ++a)
      key.push_back(vertex_signature[static_cast<std::size_t>(mesh.elements(e, a))]);
    std::sort(key.begin(), key.end());
    key.erase(std::unique(key.begin(), key.end()), key.end());
    int group = 0;
    if (const auto found = element_key_group.find(key); found != element_key_group.end()) {
      group = found->second;
    } else {
      std::vector<int> columns;
      for (int s : key) columns.insert(columns.end(), signatures[static_cast<std::size_t>(s)].begin(),
                                       signatures[static_cast<std::size_t>(s)].end());
      std::sort(columns.begin(), columns.end());
      columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
      const auto [it, inserted] = columns_group.emplace(columns, static_cast<int>(groups_.size()));
      if (inserted) groups_.push_back(Group{columns, {}});
      element_key_group.emplace(key, it->second);
      group = it->second;
    }
    mesh_element_group[static_cast<std::size_t>(e)] = group;
  }
  // The elastic terms (StVK only: the polynomial is exact for it) and, per group and term, the
  // term's elements in the group.
  std::vector<const EnergyTerm*> elastic;
  for (const auto& term : model.terms()) {
    const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(term.get());
    const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(term.get());
    if (!t3 && !t2) continue;
    const std::string material = t3 ? t3->material().name() : t2->material().name();
    if (material != "stvk")
      throw std::invalid_argument("LocalReducedStvk: term '" + term->name() + "' uses the material '" + material +
                                  "'; the exact polynomial precomputation needs StVK (other materials need a "
                                  "cubature rule)");
    elastic.push_back(term.get());
  }
  if (elastic.empty()) throw std::invalid_argument("LocalReducedStvk: the model has no elastic term");
  std::vector<std::vector<std::vector<int>>> members(groups_.size(), std::vector<std::vector<int>>(elastic.size()));
  for (std::size_t t = 0; t < elastic.size(); ++t) {
    const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(elastic[t]);
    const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(elastic[t]);
    const std::vector<int>& covered = t3 ? t3->elements() : t2->elements();
    for (std::size_t k = 0; k < covered.size(); ++k)
      members[static_cast<std::size_t>(mesh_element_group[static_cast<std::size_t>(covered[k])])][t].push_back(
          static_cast<int>(k));
  }
  std::vector<Group> built;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    Group& group = groups_[g];
    bool any = false;
    for (const auto& list : members[g]) any = any || !list.empty();
    if (group.columns.empty() || !any) continue;  // elements no column moves carry no energy
    const int k = static_cast<int>(group.columns.size()), width = k + k * (k + 1) / 2;
    Matrix basis_t(k, n);
    for (int j = 0; j < k; ++j) basis_t.row(j) = basis.col(group.columns[static_cast<std::size_t>(j)]).transpose();
    Matrix gram = Matrix::Zero(width, width);
    for (std::size_t t = 0; t < elastic.size(); ++t) {
      if (members[g][t].empty()) continue;
      if (const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(elastic[t]))
        add_group_elements(3, [&](int e) { return element_data(*t3, p, e); }, basis_t, members[g][t], gram);
      else if (const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(elastic[t]))
        add_group_elements(2, [&](int e) { return element_data(*t2, p, e); }, basis_t, members[g][t], gram);
    }
    group.lower.reserve(static_cast<std::size_t>(width) * (width + 1) / 2);
    for (int j = 0; j < width; ++j) group.lower.insert(group.lower.end(), gram.col(j).data() + j, gram.col(j).data() + width);
    built.push_back(std::move(group));
  }
  groups_ = std::move(built);
  precomputation_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  precomputation_cpu_seconds_ = static_cast<double>(std::clock() - cpu_begin) / CLOCKS_PER_SEC;
}

std::size_t LocalReducedStvk::coefficient_bytes() const {
  std::size_t bytes = 0;
  for (const Group& g : groups_) bytes += g.lower.size() * sizeof(double);
  return bytes;
}

LocalReducedStvk::~LocalReducedStvk() = default;

int LocalReducedStvk::largest_group() const {
  std::size_t most = 0;
  for (const Group& g : groups_) most = std::max(most, g.columns.size());
  return static_cast<int>(most);
}

// The polynomial W = 1/2 w^T G w, w = [q; s], s = (q_a q_b)_{a <= b}, and its derivatives as in
// evaluate_stvk_polynomial (reduced_stvk.cpp), with G = [[A, B], [B^T, D]] read once from its
// packed lower triangle: column i < r holds A(i.., i) and B^T(:, i) = B(i, :), column r + p
// holds D(p.., p). Per column: its share of y = G w (symmetric), and for the tangent the row i
// of B J_s (from B(i, :)) or, for pair p = (a, b), the axpys of L J_s (L: D's lower triangle,
// d s_p / dq_b = q_a, d s_p / dq_a = q_b, 2 q_a when a = b).
void LocalReducedStvk::evaluate_group(const Group& group, const Vector& q, double* energy, Vector* force,
                                      Matrix* stiffness) {
  const int r = static_cast<int>(q.size()), P = r * (r + 1) / 2, width = r + P;
  Vector w(width);
  w.head(r) = q;
  for (int a = 0, k = r; a < r; ++a)
    for (int b = a; b < r; ++b, ++k) w[k] = q[a] * q[b];
  // J_s^T v for v on the pairs: d/dq of sum_p v_p s_p at fixed v (added to out).
  const auto pairs_transpose = [&](const auto& v, auto&& out) {
    for (int a = 0, k = 0; a < r; ++a) {
      out[a] += 2.0 * v[k] * q[a];
      ++k;
      for (int b = a + 1; b < r; ++b, ++k) {
        out[a] += v[k] * q[b];
        out[b] += v[k] * q[a];
      }
    }
  };
  Vector y = Vector::Zero(width), d_diagonal;
  Matrix lower_j, b_j, K;
  if (stiffness) {
    lower_j = Matrix::Zero(P, r);
    b_j = Matrix::Zero(r, r);
    K.resize(r, r);
    d_diagonal.resize(P);
  }
  const double* column = group.lower.data();
  for (int j = 0; j < r; ++j) {
    const int length = width - j;
    const Eigen::Map<const Vector> c(column, length);
    y[j] += c.dot(w.tail(length));
    y.tail(length - 1).noalias() += w[j] * c.tail(length - 1);
    if (stiffness) {
      K.col(j).tail(r - j) = c.head(r - j);
      K.row(j).tail(r - j) = c.head(r - j).transpose();
      Vector row = Vector::Zero(r);
      pairs_transpose(c.tail(P), row);
      b_j.row(j) = row.transpose();
    }
    column += length;
  }
  for (int a = 0, p = 0; a < r; ++a)
    for (int b = a; b < r; ++b, ++p) {
      const int length = P - p;
      const Eigen::Map<const Vector> c(column, length);
      y[r + p] += c.dot(w.tail(length));
      y.tail(length - 1).noalias() += w[r + p] * c.tail(length - 1);
      if (stiffness) {
        d_diagonal[p] = c[0];
        if (a == b) {
          lower_j.col(a).tail(length).noalias() += (2.0 * q[a]) * c;
        } else {
          lower_j.col(b).tail(length).noalias() += q[a] * c;
          lower_j.col(a).tail(length).noalias() += q[b] * c;
        }
      }
      column += length;
    }
  if (energy) *energy = 0.5 * w.dot(y);
  if (force) {
    *force = y.head(r);
    pairs_transpose(y.tail(P), *force);
  }
  if (stiffness) {
    // A + B J_s + (B J_s)^T + X + X^T - J_s^T diag(D) J_s + sum_p y_p d2 s_p / dq2, X = J_s^T L J_s.
    Matrix x = Matrix::Zero(r, r);
    for (int c = 0; c < r; ++c) pairs_transpose(lower_j.col(c), x.col(c));
    K += b_j + b_j.transpose() + x + x.transpose();
    for (int a = 0, p = 0; a < r; ++a) {
      const int k = r + p;
      K(a, a) += 2.0 * y[k] - 4.0 * d_diagonal[p] * q[a] * q[a];
      ++p;
      for (int b = a + 1; b < r; ++b, ++p) {
        const double d = d_diagonal[p];
        K(a, a) -= d * q[b] * q[b];
        K(b, b) -= d * q[a] * q[a];
        const double off = y[r + p] - d * q[a] * q[b];
        K(a, b) += off;
        K(b, a) += off;
      }
    }
    *stiffness = std::move(K);
  }
}

void LocalReducedStvk::evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const {
  if (q.size() != r_)
    throw std::invalid_argument("LocalReducedStvk: q has " + std::to_string(q.size()) + " entries, expected " +
                                std::to_string(r_));
  const int count = static_cast<int>(groups_.size());
  std::vector<double> energies(static_cast<std::size_t>(count), 0.0);
  std::vector<Vector> forces(static_cast<std::size_t>(count));
  std::vector<Matrix> stiffnesses(static_cast<std::size_t>(count));
  // Groups in parallel into their own outputs (the sweeps allocate nothing shared and throw
  // nothing), summed below in group order: the same result with any thread count.
#pragma omp parallel for schedule(dynamic, 1) if (count > 1)
  for (int g = 0; g < count; ++g) {
    const Group& group = groups_[static_cast<std::size_t>(g)];
    Vector qg(static_cast<Eigen::Index>(group.columns.size()));
    for (std::size_t j = 0; j < group.columns.size(); ++j) qg[static_cast<Eigen::Index>(j)] = q[group.columns[j]];
    evaluate_group(group, qg, energy ? &energies[static_cast<std::size_t>(g)] : nullptr,
                   force ? &forces[static_cast<std::size_t>(g)] : nullptr,
                   stiffness ? &stiffnesses[static_cast<std::size_t>(g)] : nullptr);
  }
  if (energy) *energy = 0.0;
  if (force) *force = Vector::Zero(r_);
  if (stiffness) *stiffness = Matrix::Zero(r_, r_);
  for (int g = 0; g < count; ++g) {
    const std::vector<int>& columns = groups_[static_cast<std::size_t>(g)].columns;
    const int k = static_cast<int>(columns.size());
    if (energy) *energy += energies[static_cast<std::size_t>(g)];
    for (int i = 0; i < k; ++i) {
      const int ci = columns[static_cast<std::size_t>(i)];
      if (force) (*force)[ci] += forces[static_cast<std::size_t>(g)][i];
      if (stiffness)
        for (int j = 0; j < k; ++j)
          (*stiffness)(ci, columns[static_cast<std::size_t>(j)]) += stiffnesses[static_cast<std::size_t>(g)](i, j);
    }
  }
}

}  // namespace tailor
