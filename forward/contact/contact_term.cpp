// The IPC barrier over vertex DOFs (see contact_term.hpp).
#include "forward/contact/contact_term.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/core/psd_projection.hpp"

namespace tailor {
namespace {

contact::Positions gather(const Vector& x, const std::vector<int>& dofs) {
  contact::Positions positions(static_cast<Eigen::Index>(dofs.size()), 3);
  for (std::size_t v = 0; v < dofs.size(); ++v)
    positions.row(static_cast<Eigen::Index>(v)) = x.segment<3>(dofs[v]).transpose();
  return positions;
}

const std::vector<int>& checked(const std::vector<int>& dofs, const contact::ContactSurface& surface,
                                int num_dofs) {
  if (static_cast<int>(dofs.size()) != surface.num_vertices)
    throw std::invalid_argument("ContactTerm: " + std::to_string(dofs.size()) + " vertex DOFs for " +
                                std::to_string(surface.num_vertices) + " surface vertices");
  for (std::size_t v = 0; v < dofs.size(); ++v)
    if (dofs[v] < 0 || dofs[v] + 2 >= num_dofs)
      throw std::invalid_argument("ContactTerm: surface vertex " + std::to_string(v) + " has DOFs " +
                                  std::to_string(dofs[v]) + ".." + std::to_string(dofs[v] + 2) +
                                  " outside 0.." + std::to_string(num_dofs - 1));
  return dofs;
}

}  // namespace

ContactTerm::ContactTerm(contact::ContactSurface surface, std::vector<int> vertex_dofs,
                         const Vector& rest_state, contact::ContactOptions options, double pattern_distance)
    : potential_(surface,
                 gather(rest_state, checked(vertex_dofs, surface, static_cast<int>(rest_state.size()))),
                 options),
      vertex_dofs_(std::move(vertex_dofs)),
      num_dofs_(static_cast<int>(rest_state.size())),
      pattern_distance_(pattern_distance) {
  if (!(pattern_distance_ > 0.0))
    throw std::invalid_argument("ContactTerm: pattern distance must be positive (infinity: dense)");
  if (std::isinf(pattern_distance_)) {
    std::vector<int> all;
    for (int dof : vertex_dofs_)
      for (int k = 0; k < 3; ++k) all.push_back(dof + k);
    slots_.add_block(all);
  } else {
    update_pattern(rest_state);
  }
}

std::vector<int> ContactTerm::stencil_dofs(const std::array<int, 4>& vertices) const {
  std::vector<int> dofs;
  dofs.reserve(12);
  for (int v : vertices)
    for (int k = 0; k < 3; ++k) dofs.push_back(vertex_dofs_[static_cast<std::size_t>(v)] + k);
  return dofs;
}

void ContactTerm::update_pattern(const Vector& x) {
  if (std::isinf(pattern_distance_)) return;
  slots_.clear();
  for (int dof : vertex_dofs_) slots_.add_block({dof, dof + 1, dof + 2});
  const contact::CandidatePairs candidates =
      contact::find_candidates(potential_.surface(), positions(x), pattern_distance_);
  for (const auto& pair : candidates.point_triangle)
    slots_.add_block(stencil_dofs(potential_.stencil(contact::PairKind::point_triangle, pair)));
  for (const auto& pair : candidates.edge_edge)
    slots_.add_block(stencil_dofs(potential_.stencil(contact::PairKind::edge_edge, pair)));
}

contact::Positions ContactTerm::positions(const Vector& x) const { return gather(x, vertex_dofs_); }

void ContactTerm::hessian_pattern(HessianPattern& pattern) const {
  pattern.insert(pattern.end(), slots_.pattern().begin(), slots_.pattern().end());
}

void ContactTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (x.size() != num_dofs_)
    throw std::invalid_argument("ContactTerm: state of size " + std::to_string(x.size()) + ", expected " +
                                std::to_string(num_dofs_));
  if (request.hessian_values) std::fill(request.hessian_values, request.hessian_values + slots_.size(), 0.0);
  const bool derivatives = request.gradient || request.hessian_values;
  if (!request.value && !derivatives) return;
  double energy = 0.0;
  potential_.for_each_active(positions(x), derivatives, [&](const contact::ActivePair& pair) {
    energy += pair.derivatives.value;
    if (!derivatives) return;
    const std::vector<int> dofs = stencil_dofs(pair.vertices);
    if (request.gradient)
      for (int i = 0; i < 12; ++i)
        (*request.gradient)[dofs[static_cast<std::size_t>(i)]] += pair.derivatives.gradient[i];
    if (!request.hessian_values) return;
    Eigen::Matrix<double, 12, 12> hessian = pair.derivatives.hessian;
    if (request.hessian_mode == HessianMode::projected) project_psd(hessian);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) {
        if (hessian(i, j) == 0.0) continue;
        const int slot = slots_.slot(dofs[static_cast<std::size_t>(i)], dofs[static_cast<std::size_t>(j)]);
        if (slot < 0)
          throw std::runtime_error("ContactTerm: contact between DOFs " +
                                   std::to_string(dofs[static_cast<std::size_t>(i)]) + " and " +
                                   std::to_string(dofs[static_cast<std::size_t>(j)]) +
                                   " lies outside the Hessian pattern; raise pattern_distance or call "
                                   "update_pattern() before the solve");
        request.hessian_values[slot] += hessian(i, j);
      }
  });
  if (request.value) *request.value += energy;
}

double ContactTerm::max_step(const Vector& x, const Vector& dx) const {
  return potential_.max_step(positions(x), gather(dx, vertex_dofs_));
}

}  // namespace tailor
