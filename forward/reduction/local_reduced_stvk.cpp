#include "forward/reduction/local_reduced_stvk.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <stdexcept>
#include <string>

#include "forward/reduction/reduced_stvk.hpp"

namespace tailor {

LocalReducedStvk::LocalReducedStvk(const Model& model, const Mesh& mesh, const Vector& p, const Matrix& basis,
                                   double zero_tolerance) {
  const auto begin = std::chrono::steady_clock::now();
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
  const auto element_group = [&](const int* dofs, int count) {
    std::vector<int> key;
    for (int i = 0; i < count; i += dim) key.push_back(vertex_signature[static_cast<std::size_t>(dofs[i] / dim)]);
    std::sort(key.begin(), key.end());
    key.erase(std::unique(key.begin(), key.end()), key.end());
    const auto found = element_key_group.find(key);
    if (found != element_key_group.end()) return found->second;
    std::vector<int> columns;
    for (int s : key) columns.insert(columns.end(), signatures[static_cast<std::size_t>(s)].begin(),
                                     signatures[static_cast<std::size_t>(s)].end());
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const auto [it, inserted] = columns_group.emplace(columns, static_cast<int>(groups_.size()));
    if (inserted) groups_.push_back(Group{columns, nullptr});
    element_key_group.emplace(key, it->second);
    return it->second;
  };
  for (int e = 0; e < mesh.num_elements(); ++e) {
    std::vector<int> dofs;
    for (int a = 0; a < mesh.elements.cols(); ++a)
      for (int k = 0; k < dim; ++k) dofs.push_back(dim * mesh.elements(e, a) + k);
    element_group(dofs.data(), static_cast<int>(dofs.size()));
  }
  std::vector<Group> built;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    Group& group = groups_[g];
    if (group.columns.empty()) continue;  // elements no column moves carry no energy
    Model sub(n);
    for (const auto& block : model.parameter_layout().blocks()) sub.parameter_layout().add(block.name, block.size);
    for (const auto& term : model.terms()) {
      std::unique_ptr<EnergyTerm> share;
      const bool split = term->share_by_elements(
          [&](const int* dofs, int count) { return element_group(dofs, count) == static_cast<int>(g); }, share);
      if (split && share) sub.add(std::move(share));
    }
    Matrix columns(n, static_cast<Eigen::Index>(group.columns.size()));
    for (std::size_t j = 0; j < group.columns.size(); ++j)
      columns.col(static_cast<Eigen::Index>(j)) = basis.col(group.columns[j]);
    if (sub.terms().empty()) continue;
    group.polynomial = std::make_unique<ReducedStvk>(sub, p, columns);
    built.push_back(std::move(group));
  }
  groups_ = std::move(built);
  precomputation_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

LocalReducedStvk::~LocalReducedStvk() = default;

int LocalReducedStvk::largest_group() const {
  std::size_t most = 0;
  for (const Group& g : groups_) most = std::max(most, g.columns.size());
  return static_cast<int>(most);
}

void LocalReducedStvk::evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const {
  if (q.size() != r_)
    throw std::invalid_argument("LocalReducedStvk: q has " + std::to_string(q.size()) + " entries, expected " +
                                std::to_string(r_));
  if (energy) *energy = 0.0;
  if (force) *force = Vector::Zero(r_);
  if (stiffness) *stiffness = Matrix::Zero(r_, r_);
  for (const Group& g : groups_) {
    const int k = static_cast<int>(g.columns.size());
    Vector qg(k);
    for (int j = 0; j < k; ++j) qg[j] = q[g.columns[static_cast<std::size_t>(j)]];
    double e = 0.0;
    Vector f;
    Matrix K;
    g.polynomial->evaluate(qg, energy ? &e : nullptr, force ? &f : nullptr, stiffness ? &K : nullptr);
    if (energy) *energy += e;
    for (int i = 0; i < k; ++i) {
      const int ci = g.columns[static_cast<std::size_t>(i)];
      if (force) (*force)[ci] += f[i];
      if (stiffness)
        for (int j = 0; j < k; ++j) (*stiffness)(ci, g.columns[static_cast<std::size_t>(j)]) += K(i, j);
    }
  }
}

}  // namespace tailor
