#include "forward/dynamics/descent_vertex_blocks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "forward/fem/elastic_term.hpp"

namespace tailor {
namespace dk = descent_kernels;

std::string VertexBlockModel::check(const Model& model) {
  const Elimination& elim = model.elimination();
  if (model.num_dofs() % 3 != 0) return "the model's DOFs are not vertices of 3";
  if (!elim.is_selection() || model.has_prescribed_parameters())
    return "the model's constraints are not a selection of DOFs (Dirichlet conditions only)";
  std::vector<int> uses(static_cast<std::size_t>(elim.num_free()), 0);
  for (int i = 0; i < model.num_dofs(); ++i)
    for (int t = elim.row_begin()[i]; t < elim.row_begin()[i + 1]; ++t)
      if (++uses[static_cast<std::size_t>(elim.row_free()[t])] > 1)
        return "a free unknown moves several DOFs (periodic or tied constraints)";
  std::string material;
  for (const auto& term : model.terms()) {
    if (term->hessian_is_constant()) continue;
    const auto* elastic = dynamic_cast<const ElasticTerm<3>*>(term.get());
    const std::string name = elastic ? elastic->material().name() : "";
    if (!elastic || (name != "neo_hookean" && name != "stvk"))
      return "term " + term->name() +
             " is not covered (tet elastic terms of neo_hookean or stvk, and terms with a constant Hessian)";
    if (!material.empty() && name != material) return "the elastic terms mix materials (" + material + ", " + name + ")";
    material = name;
  }
  return "";
}

VertexBlockModel::VertexBlockModel(const Model& model) : model_(model) {
  if (const std::string why = check(model); !why.empty())
    throw std::invalid_argument("descent: the vertex-block rule (and the GPU path) does not cover this model: " + why +
                                "; use the CPU with preconditioner \"projected_hessian\"");
  const Elimination& elim = model.elimination();
  const int n = model.num_dofs();
  num_free_ = elim.num_free();
  free_of_dof_.assign(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i)
    for (int t = elim.row_begin()[i]; t < elim.row_begin()[i + 1]; ++t) free_of_dof_[i] = elim.row_free()[t];
  // Blocks: the vertices with a free unknown.
  std::vector<int> block_of_vertex(static_cast<std::size_t>(n / 3), -1);
  for (int v = 0; v < n / 3; ++v) {
    if (free_of_dof_[3 * v] < 0 && free_of_dof_[3 * v + 1] < 0 && free_of_dof_[3 * v + 2] < 0) continue;
    block_of_vertex[v] = static_cast<int>(block_vertex_.size());
    block_vertex_.push_back(v);
    for (int k = 0; k < 3; ++k) block_free_.push_back(free_of_dof_[3 * v + k]);
  }
  // Tets, in term order.
  for (const auto& term : model.terms()) {
    if (term->hessian_is_constant()) {
      constant_terms_.push_back(term.get());
      continue;
    }
    const auto* elastic = dynamic_cast<const ElasticTerm<3>*>(term.get());
    material_ = elastic->material().name() == "stvk" ? dk::kStvk : dk::kNeoHookean;
    elastic_terms_.emplace_back(elastic, num_tets());
    for (int k = 0; k < static_cast<int>(elastic->elements().size()); ++k) {
      for (int a = 0; a < 4; ++a) {
        tet_vertex_.push_back(elastic->element_vertices(k)[a]);
        for (int j = 0; j < 3; ++j) tet_shape_.push_back(elastic->shape_gradients(k)(a, j));
      }
      tet_volume_.push_back(elastic->rest_volume(k));
    }
  }
  tet_lame_.assign(2 * tet_volume_.size(), 0.0);
  // Incidence: the corners 4 t + a of each block's vertex, in increasing order (a counting sort).
  const int blocks = static_cast<int>(block_vertex_.size());
  incidence_begin_.assign(static_cast<std::size_t>(blocks) + 1, 0);
  for (const int v : tet_vertex_)
    if (block_of_vertex[v] >= 0) ++incidence_begin_[block_of_vertex[v] + 1];
  for (int b = 0; b < blocks; ++b) incidence_begin_[b + 1] += incidence_begin_[b];
  incidence_.resize(static_cast<std::size_t>(incidence_begin_[blocks]));
  std::vector<int> fill(incidence_begin_.begin(), incidence_begin_.end() - 1);
  for (int c = 0; c < static_cast<int>(tet_vertex_.size()); ++c)
    if (const int b = block_of_vertex[tet_vertex_[c]]; b >= 0) incidence_[fill[b]++] = c;
  // A's pattern: the constant terms' slots between free unknowns, summed per (row, col).
  std::vector<std::tuple<int, int, int>> entries;  // (row, col, slot)
  int slot = 0;
  for (const EnergyTerm* term : constant_terms_) {
    HessianPattern pattern;
    term->hessian_pattern(pattern);
    for (const auto& [row, col] : pattern) {
      if (free_of_dof_[row] >= 0 && free_of_dof_[col] >= 0) entries.emplace_back(free_of_dof_[row], free_of_dof_[col], slot);
      ++slot;
    }
  }
  slot_values_.assign(static_cast<std::size_t>(slot), 0.0);
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return std::get<0>(a) != std::get<0>(b) ? std::get<0>(a) < std::get<0>(b) : std::get<1>(a) < std::get<1>(b);
  });
  a_begin_.assign(static_cast<std::size_t>(num_free_) + 1, 0);
  for (std::size_t t = 0; t < entries.size(); ++t) {
    const auto [row, col, s] = entries[t];
    if (t == 0 || row != std::get<0>(entries[t - 1]) || col != std::get<1>(entries[t - 1])) {
      a_col_.push_back(col);
      a_slot_begin_.push_back(static_cast<int>(a_slot_.size()));
      ++a_begin_[row + 1];
    }
    a_slot_.push_back(s);
  }
  a_slot_begin_.push_back(static_cast<int>(a_slot_.size()));
  for (int i = 0; i < num_free_; ++i) a_begin_[i + 1] += a_begin_[i];
  a_value_.assign(a_col_.size(), 0.0);
  constant_blocks_.assign(9 * static_cast<std::size_t>(blocks), 0.0);
}

bool VertexBlockModel::prepare(const Vector& p, const Vector& y) {
  const Vector x = model_.state(y, p);
  positions_.assign(x.data(), x.data() + x.size());
  y0_.assign(y.data(), y.data() + y.size());
  std::vector<std::uint64_t> revisions;
  for (const EnergyTerm* term : constant_terms_) revisions.push_back(term->hessian_revision());
  const bool fresh = parameters_valid_ && parameters_p_.size() == p.size() && parameters_p_ == p && revisions == revisions_;
  if (!fresh) {
    for (const auto& [term, first] : elastic_terms_) {
      const auto* elastic = static_cast<const ElasticTerm<3>*>(term);
      for (int k = 0; k < static_cast<int>(elastic->elements().size()); ++k) {
        const LameParameters lame = elastic->element_lame(p, k);
        tet_lame_[2 * static_cast<std::size_t>(first + k)] = lame.lambda;
        tet_lame_[2 * static_cast<std::size_t>(first + k) + 1] = lame.mu;
      }
    }
    std::size_t offset = 0;
    for (const EnergyTerm* term : constant_terms_) {
      HessianPattern pattern;
      term->hessian_pattern(pattern);
      EnergyRequest request;
      request.hessian_values = slot_values_.data() + offset;
      if (!pattern.empty()) term->evaluate(x, p, request);
      offset += pattern.size();
    }
    std::fill(constant_blocks_.begin(), constant_blocks_.end(), 0.0);
    std::vector<int> block_of_free(static_cast<std::size_t>(num_free_)), component(static_cast<std::size_t>(num_free_));
    for (std::size_t b = 0; b < block_vertex_.size(); ++b)
      for (int k = 0; k < 3; ++k)
        if (const int f = block_free_[3 * b + k]; f >= 0) block_of_free[f] = static_cast<int>(b), component[f] = k;
    for (int i = 0; i < num_free_; ++i)
      for (int e = a_begin_[i]; e < a_begin_[i + 1]; ++e) {
        double s = 0.0;
        for (int t = a_slot_begin_[e]; t < a_slot_begin_[e + 1]; ++t) s += slot_values_[a_slot_[t]];
        a_value_[e] = s;
        const int j = a_col_[e];
        if (block_of_free[i] == block_of_free[j])
          constant_blocks_[9 * static_cast<std::size_t>(block_of_free[i]) + 3 * component[i] + component[j]] += s;
      }
    parameters_valid_ = true;
    parameters_p_ = p;
    revisions_ = std::move(revisions);
  }
  // The constant part's value and gradient at the start.
  Vector gradient_x = Vector::Zero(x.size());
  e0_ = 0.0, constant_magnitude_ = 0.0;
  for (const EnergyTerm* term : constant_terms_) {
    double energy = 0.0;
    EnergyRequest request;
    request.value = &energy;
    request.gradient = &gradient_x;
    term->evaluate(x, p, request);
    e0_ += energy;
    constant_magnitude_ += std::abs(energy);
  }
  const Vector g0 = model_.elimination().reduce(gradient_x);
  g0_.assign(g0.data(), g0.data() + g0.size());
  return !fresh;
}

dk::VertexBlockLayout VertexBlockModel::layout() const {
  dk::VertexBlockLayout L;
  L.material = material_;
  L.num_tets = num_tets();
  L.tet_vertex = tet_vertex_.data();
  L.tet_shape = tet_shape_.data();
  L.tet_volume = tet_volume_.data();
  L.tet_lame = tet_lame_.data();
  L.num_blocks = static_cast<int>(block_vertex_.size());
  L.block_vertex = block_vertex_.data();
  L.block_free = block_free_.data();
  L.incidence_begin = incidence_begin_.data();
  L.incidence = incidence_.data();
  L.constant_blocks = constant_blocks_.data();
  L.num_free = num_free_;
  L.a_begin = a_begin_.data();
  L.a_col = a_col_.data();
  L.a_value = a_value_.data();
  L.g0 = g0_.data();
  L.y0 = y0_.data();
  return L;
}

void VertexBlockHostPass::evaluate(const Vector& y, Result& out, bool with_blocks) {
  const dk::VertexBlockLayout L = model_.layout();
  positions_ = model_.start_positions();
  tet_energy_.resize(static_cast<std::size_t>(L.num_tets));
  tet_gradient_.resize(12 * static_cast<std::size_t>(L.num_tets));
  if (with_blocks) tet_blocks_.resize(36 * static_cast<std::size_t>(L.num_tets));
  quadratic_gradient_.resize(static_cast<std::size_t>(L.num_free));
  quadratic_energy_.resize(static_cast<std::size_t>(L.num_free));
  out.gradient.resize(L.num_free);
  if (with_blocks) out.block_inverse.resize(9 * static_cast<std::size_t>(L.num_blocks));
  const double* yd = y.data();
  // One parallel region for the four loops (small meshes stay on the calling thread, as in the
  // element loop): each item writes only its own outputs, so any split gives the same result.
#pragma omp parallel if (L.num_tets > 256)
  {
#pragma omp for schedule(static)
    for (int b = 0; b < L.num_blocks; ++b) dk::scatter_block(L, b, yd, positions_.data());
#pragma omp for schedule(static)
    for (int t = 0; t < L.num_tets; ++t)
      dk::tet_item(L, t, positions_.data(), tet_energy_.data(), tet_gradient_.data(), tet_blocks_.data(), with_blocks);
#pragma omp for schedule(static)
    for (int i = 0; i < L.num_free; ++i)
      dk::quadratic_row(L, i, yd, quadratic_gradient_.data(), quadratic_energy_.data());
#pragma omp for schedule(static)
    for (int b = 0; b < L.num_blocks; ++b)
      dk::gather_block(L, b, tet_gradient_.data(), tet_blocks_.data(), quadratic_gradient_.data(), out.gradient.data(),
                       out.block_inverse.data(), with_blocks);
  }
  // Sums in index order: the same for every thread count.
  double elastic = 0.0, quadratic = 0.0;
  for (const double e : tet_energy_) elastic += e;
  for (const double e : quadratic_energy_) quadratic += e;
  out.energy = elastic + model_.e0() + quadratic;
  out.energy_roundoff = 1e3 * std::numeric_limits<double>::epsilon() * (std::abs(elastic) + model_.constant_magnitude());
}

void VertexBlockHostPass::apply_inverse(const Result& at, const Vector& gradient, Vector& direction) const {
  // The Chebyshev block step with omega = 1, alpha = -1 and previous = u = 0: next = D^-1 g.
  const dk::VertexBlockLayout L = model_.layout();
  direction.resize(gradient.size());
  const std::vector<double> zero(static_cast<std::size_t>(L.num_free), 0.0);
#pragma omp parallel for schedule(static) if (L.num_blocks > 4096)
  for (int b = 0; b < L.num_blocks; ++b)
    dk::chebyshev_block(L.block_free, at.block_inverse.data(), b, gradient.data(), zero.data(), zero.data(), -1.0, 1.0,
                        direction.data());
}

}  // namespace tailor
