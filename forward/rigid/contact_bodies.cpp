// Rigid and deformable contact surfaces over the model's DOFs (see contact_bodies.hpp).
#include "forward/rigid/contact_bodies.hpp"

#include <algorithm>
#include <stdexcept>

#include "forward/core/psd_projection.hpp"

namespace tailor::rigid {

ContactBodies::ContactBodies(const RigidBodySystem& system, std::vector<DeformableSurface> deformable,
                             int num_dofs)
    : system_(system),
      deformable_(std::move(deformable)),
      num_dofs_(num_dofs < 0 ? system.num_dofs() : num_dofs) {
  const contact::ContactSurface& rigid = system.surface();
  int total = rigid.num_vertices;
  for (const DeformableSurface& d : deformable_) {
    for (int dof : d.vertex_dofs)
      if (dof < system.num_dofs() || dof + 2 >= num_dofs_)
        throw std::invalid_argument("contact bodies: deformable surface '" + d.name +
                                    "' has a vertex at DOFs " + std::to_string(dof) + ".." +
                                    std::to_string(dof + 2) + ", outside " +
                                    std::to_string(system.num_dofs()) + ".." + std::to_string(num_dofs_ - 1));
    total += static_cast<int>(d.vertex_dofs.size());
  }
  Eigen::MatrixX3i faces = rigid.faces;
  Eigen::MatrixX2i edges(0, 2);
  std::vector<int> groups(rigid.groups);
  if (groups.empty()) groups.assign(static_cast<std::size_t>(rigid.num_vertices), 0);
  for (int v = 0; v < rigid.num_vertices; ++v) {
    vertex_body_.push_back(system.body_of(v));
    vertex_dof_.push_back(6 * system.body_of(v));
    body_frame_.push_back(system.body_frame(v));
  }
  int offset = rigid.num_vertices;
  for (std::size_t i = 0; i < deformable_.size(); ++i) {
    const DeformableSurface& d = deformable_[i];
    const int n = static_cast<int>(d.vertex_dofs.size());
    if ((d.faces.size() > 0 && (d.faces.minCoeff() < 0 || d.faces.maxCoeff() >= n)) ||
        (d.extra_edges.size() > 0 && (d.extra_edges.minCoeff() < 0 || d.extra_edges.maxCoeff() >= n)))
      throw std::invalid_argument("contact bodies: deformable surface '" + d.name +
                                  "' has a face or edge index outside its " + std::to_string(n) +
                                  " vertices");
    const Eigen::Index edge_rows = edges.rows();
    edges.conservativeResize(edge_rows + d.extra_edges.rows(), 2);
    edges.bottomRows(d.extra_edges.rows()) = d.extra_edges.array() + offset;
    deformable_offset_.push_back(offset);
    const Eigen::Index rows = faces.rows();
    faces.conservativeResize(rows + d.faces.rows(), 3);
    faces.bottomRows(d.faces.rows()) = d.faces.array() + offset;
    for (int v = 0; v < n; ++v) {
      vertex_body_.push_back(-1);
      vertex_dof_.push_back(d.vertex_dofs[static_cast<std::size_t>(v)]);
      body_frame_.push_back(Eigen::Vector3d::Zero());
      groups.push_back(system.num_bodies() + static_cast<int>(i));
    }
    offset += n;
  }
  surface_ = contact::ContactSurface::from_faces(total, faces, groups, edges);
}

contact::Positions ContactBodies::positions(const Vector& q) const {
  if (q.size() != num_dofs_)
    throw std::invalid_argument("contact bodies: state of size " + std::to_string(q.size()) + ", expected " +
                                std::to_string(num_dofs_));
  contact::Positions x(surface_.num_vertices, 3);
  const int rigid_vertices = system_.surface().num_vertices;
  x.topRows(rigid_vertices) = system_.world_positions(q.head(system_.num_dofs()));
  for (int v = rigid_vertices; v < surface_.num_vertices; ++v) x.row(v) = q.segment<3>(dof_of(v)).transpose();
  return x;
}

std::vector<RotationDerivatives> ContactBodies::rotations(const Vector& q) const {
  std::vector<RotationDerivatives> r;
  r.reserve(static_cast<std::size_t>(system_.num_bodies()));
  for (int b = 0; b < system_.num_bodies(); ++b) r.push_back(rotation_derivatives(q.segment<3>(6 * b + 3)));
  return r;
}

void ContactBodies::add_pattern(contact::SlotMap& slots) const {
  std::vector<int> rigid(static_cast<std::size_t>(system_.num_dofs()));
  for (int i = 0; i < system_.num_dofs(); ++i) rigid[static_cast<std::size_t>(i)] = i;
  slots.add_block(rigid);
  auto vertex_dofs = [&](int v, std::vector<int>& dofs) {
    for (int k = 0; k < 3; ++k) dofs.push_back(dof_of(v) + k);
  };
  const int first_deformable = system_.surface().num_vertices;
  for (int v = first_deformable; v < surface_.num_vertices; ++v) {
    std::vector<int> block = rigid;
    vertex_dofs(v, block);
    slots.add_block(block);
  }
  for (int f = 0; f < surface_.faces.rows(); ++f) {
    if (surface_.faces(f, 0) < first_deformable) continue;
    std::vector<int> block;
    for (int k = 0; k < 3; ++k) vertex_dofs(surface_.faces(f, k), block);
    slots.add_block(block);
  }
  for (int e = 0; e < surface_.edges.rows(); ++e) {
    if (surface_.edges(e, 0) < first_deformable) continue;
    std::vector<int> block;
    for (int k = 0; k < 2; ++k) vertex_dofs(surface_.edges(e, k), block);
    slots.add_block(block);
  }
  for (std::size_t i = 0; i < deformable_.size(); ++i)
    for (std::size_t j = i + 1; j < deformable_.size(); ++j) {
      std::vector<int> block;
      for (std::size_t s : {i, j})
        for (int dof : deformable_[s].vertex_dofs)
          for (int k = 0; k < 3; ++k) block.push_back(dof + k);
      slots.add_block(block);
    }
}

namespace {

// The DOF blocks of a stencil: rigid bodies (6 DOFs) and deformable vertices (3 DOFs), in
// order of appearance, with the Jacobian dx/dq of the 12 stencil coordinates.
struct StencilMap {
  using Jacobian = Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, 24>;
  std::array<int, 4> key{}, column{};  // key: rigid body b >= 0, or -1 - v (deformable vertex v)
  int count = 0;
  std::vector<int> dofs;
  Jacobian J;
};

StencilMap stencil_map(const ContactBodies& bodies, const std::array<int, 4>& vertices,
                       const std::vector<RotationDerivatives>& rotations) {
  StencilMap m;
  std::array<int, 4> vertex_column{};
  for (int k = 0; k < 4; ++k) {
    const int v = vertices[static_cast<std::size_t>(k)], b = bodies.body_of(v);
    const int key = b >= 0 ? b : -1 - v;
    int block = 0;
    while (block < m.count && m.key[static_cast<std::size_t>(block)] != key) ++block;
    if (block == m.count) {
      m.key[static_cast<std::size_t>(m.count++)] = key;
      m.column[static_cast<std::size_t>(block)] = static_cast<int>(m.dofs.size());
      const int first = b >= 0 ? 6 * b : bodies.dof_of(v), size = b >= 0 ? 6 : 3;
      for (int i = 0; i < size; ++i) m.dofs.push_back(first + i);
    }
    vertex_column[static_cast<std::size_t>(k)] = m.column[static_cast<std::size_t>(block)];
  }
  m.J = StencilMap::Jacobian::Zero(12, static_cast<Eigen::Index>(m.dofs.size()));
  for (int k = 0; k < 4; ++k) {
    const int v = vertices[static_cast<std::size_t>(k)], b = bodies.body_of(v),
              c = vertex_column[static_cast<std::size_t>(k)];
    m.J.block<3, 3>(3 * k, c).setIdentity();
    if (b < 0) continue;
    const RotationDerivatives& r = rotations[static_cast<std::size_t>(b)];
    for (int l = 0; l < 3; ++l)
      m.J.block<3, 1>(3 * k, c + 3 + l) = r.first[static_cast<std::size_t>(l)] * bodies.body_frame(v);
  }
  m.column = vertex_column;
  return m;
}

}  // namespace

void ContactBodies::add_stencil_gradient(const std::array<int, 4>& vertices,
                                         const Eigen::Matrix<double, 12, 1>& g,
                                         const std::vector<RotationDerivatives>& rotations,
                                         Vector& gradient) const {
  const StencilMap m = stencil_map(*this, vertices, rotations);
  const Eigen::VectorXd gq = m.J.transpose() * g;
  for (Eigen::Index i = 0; i < gq.size(); ++i) gradient[m.dofs[static_cast<std::size_t>(i)]] += gq[i];
}

void ContactBodies::add_stencil(const std::array<int, 4>& vertices, const Eigen::Matrix<double, 12, 1>& g,
                                const Eigen::Matrix<double, 12, 12>& H,
                                const std::vector<RotationDerivatives>& rotations,
                                const contact::SlotMap& slots, const EnergyRequest& request) const {
  const StencilMap m = stencil_map(*this, vertices, rotations);
  if (request.gradient) {
    const Eigen::VectorXd gq = m.J.transpose() * g;
    for (Eigen::Index i = 0; i < gq.size(); ++i)
      (*request.gradient)[m.dofs[static_cast<std::size_t>(i)]] += gq[i];
  }
  if (!request.hessian_values) return;
  Eigen::MatrixXd Hq = m.J.transpose() * H * m.J;
  for (int k = 0; k < 4; ++k) {
    const int v = vertices[static_cast<std::size_t>(k)], b = body_of(v),
              c = m.column[static_cast<std::size_t>(k)];
    if (b < 0) continue;
    const RotationDerivatives& r = rotations[static_cast<std::size_t>(b)];
    const Eigen::Vector3d gk = g.segment<3>(3 * k);
    for (int l = 0; l < 3; ++l)
      for (int n = 0; n < 3; ++n)
        Hq(c + 3 + l, c + 3 + n) +=
            gk.dot(r.second[static_cast<std::size_t>(l)][static_cast<std::size_t>(n)] * body_frame(v));
  }
  if (request.hessian_mode == HessianMode::projected) project_psd(Hq);
  for (Eigen::Index i = 0; i < Hq.rows(); ++i)
    for (Eigen::Index j = 0; j < Hq.cols(); ++j) {
      if (Hq(i, j) == 0.0) continue;
      const int row = m.dofs[static_cast<std::size_t>(i)], col = m.dofs[static_cast<std::size_t>(j)];
      const int slot = slots.slot(row, col);
      if (slot < 0)
        throw std::logic_error("contact bodies: entry (" + std::to_string(row) + ", " + std::to_string(col) +
                               ") lies outside the contact Hessian pattern");
      request.hessian_values[slot] += Hq(i, j);
    }
}

double ContactBodies::max_step(const Vector& q, const Vector& dq,
                               const contact::ContactPotential& potential) const {
  if (!dq.allFinite() || !q.allFinite()) return 0.0;  // a NaN or infinite direction: no safe step
  const contact::Positions x = positions(q);
  const int n = surface_.num_vertices;
  Eigen::VectorXd bound(n);  // path length bound of each vertex over t in [0, 1]
  for (int v = 0; v < n; ++v) {
    const int b = body_of(v);
    bound[v] = b >= 0 ? dq.segment<3>(6 * b).norm() + dq.segment<3>(6 * b + 3).norm() * body_frame(v).norm()
                      : dq.segment<3>(dof_of(v)).norm();
  }
  if (!(bound.maxCoeff() > 0.0)) return 1.0;
  const contact::CandidatePairs candidates = contact::find_candidates(surface_, x, 0.0, nullptr, &bound);
  const contact::CcdOptions& ccd = potential.options().ccd;
  double step = 1.0;
  long budget = ccd.max_total_iterations;  // evaluations left for this call
  auto run = [&](contact::PairKind kind, const std::array<int, 2>& candidate) {
    const std::array<int, 4> v = potential.stencil(kind, candidate);
    // Each point moves by a translation u_k (dT of its body, or its own dx) plus, on a rigid
    // body, a rotation whose path is at most |dw| |V| long. A common translation c of the four
    // points leaves their distance unchanged: subtract the one (0 or one of the u_k) that gives
    // the smallest rate bound, e.g. the translation of one body when two bodies move together.
    std::array<Eigen::Vector3d, 4> u;
    std::array<double, 4> spin;
    for (int k = 0; k < 4; ++k) {
      const int vk = v[static_cast<std::size_t>(k)], b = body_of(vk);
      u[static_cast<std::size_t>(k)] = b >= 0 ? dq.segment<3>(6 * b) : dq.segment<3>(dof_of(vk));
      spin[static_cast<std::size_t>(k)] =
          b >= 0 ? dq.segment<3>(6 * b + 3).norm() * body_frame(vk).norm() : 0.0;
    }
    auto rate_with = [&](const Eigen::Vector3d& c) {
      std::array<double, 4> L;
      for (std::size_t k = 0; k < 4; ++k) L[k] = (u[k] - c).norm() + spin[k];
      return kind == contact::PairKind::point_triangle ? L[0] + std::max({L[1], L[2], L[3]})
                                                       : std::max(L[0], L[1]) + std::max(L[2], L[3]);
    };
    Eigen::Vector3d common = Eigen::Vector3d::Zero();
    double rate = rate_with(common);
    for (const Eigen::Vector3d& c : u)
      if (const double r = rate_with(c); r < rate) {
        rate = r;
        common = c;
      }
    if (!(rate > 0.0)) return;
    const contact::StencilPath path = [&](double t, std::array<contact::Point, 4>& points) {
      for (int k = 0; k < 4; ++k) {
        const int vk = v[static_cast<std::size_t>(k)], b = body_of(vk);
        if (b < 0) {
          points[static_cast<std::size_t>(k)] =
              q.segment<3>(dof_of(vk)) + t * (dq.segment<3>(dof_of(vk)) - common);
          continue;
        }
        const Eigen::Vector3d T = q.segment<3>(6 * b) + t * (dq.segment<3>(6 * b) - common);
        const Eigen::Vector3d w = q.segment<3>(6 * b + 3) + t * dq.segment<3>(6 * b + 3);
        points[static_cast<std::size_t>(k)] = T + rotation_matrix(w) * body_frame(vk);
      }
    };
    const contact::CcdResult r =
        contact::additive_ccd_query(kind, path, rate, step, ccd, std::min(ccd.max_iterations, budget));
    budget -= r.iterations;
    step = std::min(step, r.step);
  };
  for (const auto& c : candidates.point_triangle) run(contact::PairKind::point_triangle, c);
  for (const auto& c : candidates.edge_edge) run(contact::PairKind::edge_edge, c);
  return step;
}

}  // namespace tailor::rigid
