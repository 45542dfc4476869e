// IPC contact between a periodic cell's mesh bodies, and the independent intersection check (see
// periodic_mesh_contact.hpp).
#include "forward/interlocking/periodic_mesh_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "forward/contact/barrier_stiffness.hpp"
#include "forward/contact/pair_potential.hpp"
#include "forward/rigid/rotation.hpp"

namespace tailor::interlocking {

PeriodicMeshContact::PeriodicMeshContact(const std::vector<std::shared_ptr<const ElementMesh>>& body_meshes,
                                         int num_masters, const Vector& rest_state, const std::vector<bool>& in_reach,
                                         double activation_distance)
    : num_cell_bodies_(static_cast<int>(body_meshes.size())) {
  std::vector<rigid::RigidBody> bodies;
  range_cap_ = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < body_meshes.size(); ++b) {
    if (!in_reach[b]) continue;
    const ElementMesh& mesh = *body_meshes[b];
    rigid::RigidBody body;
    body.name = "element_" + std::to_string(b);
    body.vertices = mesh.vertices;
    body.faces = mesh.faces;
    // Images are "fixed" for the contact surface only: one group, so they never meet each other.
    body.fixed = static_cast<int>(b) >= num_masters;
    bodies.push_back(std::move(body));
    bodies_.push_back(static_cast<int>(b));
    range_cap_ = std::min(range_cap_, mesh_bounding_radius(mesh));
  }
  system_ = std::make_unique<rigid::RigidBodySystem>(std::move(bodies));
  contact::ContactOptions options;
  options.activation_distance = activation_distance;
  options.stiffness = contact::stiffness_for_force(1.0, activation_distance);
  term_ = std::make_unique<rigid::RigidContactTerm>(std::make_shared<const rigid::ContactBodies>(*system_),
                                                    contact_state(rest_state), options);
}

Vector PeriodicMeshContact::contact_state(const Vector& x) const {
  Vector q(6 * static_cast<Eigen::Index>(bodies_.size()));
  for (std::size_t c = 0; c < bodies_.size(); ++c)
    q.segment<6>(6 * static_cast<Eigen::Index>(c)) = x.segment<6>(6 * bodies_[c]);
  return q;
}

void PeriodicMeshContact::evaluate(const Vector& x, double* energy, Vector* gradient, SparseMatrix* hessian,
                                   HessianMode mode) const {
  const Vector q = contact_state(x);
  // One pass of the term for every output (its candidate search dominates the cost).
  double value = 0.0;
  Vector g = Vector::Zero(q.size());
  std::vector<double> values(hessian ? term_->slots().size() : 0);
  EnergyRequest request;
  request.value = &value;
  request.gradient = gradient ? &g : nullptr;
  request.hessian_values = hessian ? values.data() : nullptr;
  request.hessian_mode = mode;
  term_->evaluate(q, Vector(), request);
  if (energy) *energy += value;
  if (gradient)
    for (std::size_t c = 0; c < bodies_.size(); ++c)
      gradient->segment<6>(6 * bodies_[c]) += g.segment<6>(6 * static_cast<Eigen::Index>(c));
  if (hessian) {
    Triplets t;
    const HessianPattern& pattern = term_->slots().pattern();
    for (std::size_t k = 0; k < pattern.size(); ++k) {
      if (values[k] == 0.0) continue;
      const int r = pattern[k].row, c = pattern[k].col;
      t.emplace_back(6 * bodies_[static_cast<std::size_t>(r / 6)] + r % 6,
                     6 * bodies_[static_cast<std::size_t>(c / 6)] + c % 6, values[k]);
    }
    hessian->resize(6 * num_cell_bodies_, 6 * num_cell_bodies_);
    hessian->setFromTriplets(t.begin(), t.end());
  }
}

double PeriodicMeshContact::max_step(const Vector& x, const Vector& dx) const {
  return term_->max_step(contact_state(x), contact_state(dx));
}

double PeriodicMeshContact::min_distance(const Vector& x, double range) const {
  return term_->min_distance(contact_state(x), std::isfinite(range) ? range : range_cap_);
}

namespace {

std::array<contact::Point, 4> stencil_points(const contact::Positions& x, const std::array<int, 4>& v) {
  std::array<contact::Point, 4> out;
  for (std::size_t k = 0; k < 4; ++k) out[k] = x.row(v[k]).transpose();
  return out;
}

// The two contact bodies of a stencil: the point's (or first edge's) and the triangle's (second
// edge's).
std::pair<int, int> stencil_bodies(const rigid::ContactBodies& bodies, contact::PairKind kind,
                                   const std::array<int, 4>& v) {
  return {bodies.body_of(v[0]), bodies.body_of(kind == contact::PairKind::point_triangle ? v[1] : v[2])};
}

}  // namespace

std::vector<tori::TorusPair> PeriodicMeshContact::close_pairs(const Vector& x, double range) const {
  const rigid::ContactBodies& bodies = term_->bodies();
  const contact::ContactPotential& potential = term_->potential();
  const contact::Positions positions = bodies.positions(contact_state(x));
  const double cap = std::isfinite(range) ? range : range_cap_;
  const contact::CandidatePairs candidates = contact::find_candidates(bodies.surface(), positions, cap);
  std::map<std::pair<int, int>, double> closest;
  const auto visit = [&](contact::PairKind kind, const std::array<int, 2>& pair) {
    const std::array<int, 4> v = potential.stencil(kind, pair);
    const double d = std::sqrt(contact::classify_pair(kind, stencil_points(positions, v)).squared_distance);
    if (!(d < cap)) return;
    const auto [ca, cb] = stencil_bodies(bodies, kind, v);
    const std::pair<int, int> key = std::minmax(cell_body(ca), cell_body(cb));
    const auto it = closest.find(key);
    if (it == closest.end() || d < it->second) closest[key] = d;
  };
  for (const auto& c : candidates.point_triangle) visit(contact::PairKind::point_triangle, c);
  for (const auto& c : candidates.edge_edge) visit(contact::PairKind::edge_edge, c);
  std::vector<tori::TorusPair> out;
  for (const auto& [key, d] : closest) {
    tori::TorusPair pair;
    pair.a = key.first;
    pair.b = key.second;
    pair.distance.distance = d;
    out.push_back(pair);
  }
  return out;
}

std::vector<tori::TorusPairForce> PeriodicMeshContact::pair_forces(const Vector& x) const {
  const rigid::ContactBodies& bodies = term_->bodies();
  std::map<std::pair<int, int>, tori::TorusPairForce> forces;
  term_->potential().for_each_active(bodies.positions(contact_state(x)), true, [&](const contact::ActivePair& pair) {
    const auto [ca, cb] = stencil_bodies(bodies, pair.kind, pair.vertices);
    const std::pair<int, int> key = std::minmax(cell_body(ca), cell_body(cb));
    tori::TorusPairForce& f = forces[key];
    const double d = std::sqrt(pair.derivatives.distance.squared_distance);
    if (f.a == f.b || d < f.distance) f.distance = d;  // a fresh entry has a = b = 0
    f.a = key.first;
    f.b = key.second;
    for (std::size_t k = 0; k < 4; ++k)
      if (cell_body(bodies.body_of(pair.vertices[k])) == key.second)
        f.force_on_b -= pair.derivatives.gradient.segment<3>(3 * static_cast<Eigen::Index>(k));
  });
  std::vector<tori::TorusPairForce> out;
  for (const auto& entry : forces) out.push_back(entry.second);
  return out;
}

// ---- The independent intersection check ----------------------------------------------------

namespace {

// Error-free transformations (Shewchuk 1997, "Adaptive precision floating-point arithmetic and
// fast robust geometric predicates", Two-Sum and Two-Product; the product's error by fma).
void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bv = s - a, av = s - bv;
  e = (a - av) + (b - bv);
}

// An expansion: nonoverlapping components in increasing magnitude (zeros allowed), exact sum.
using Expansion = std::vector<double>;

// Grow-Expansion (Shewchuk, Theorem 10): e + b, exactly.
void grow(Expansion& e, double b) {
  double q = b;
  for (double& c : e) {
    double s, err;
    two_sum(q, c, s, err);
    c = err;
    q = s;
  }
  e.push_back(q);
}

Expansion difference(double a, double b) {
  double s, e;
  two_sum(a, -b, s, e);
  return {e, s};
}

Expansion product(const Expansion& a, const Expansion& b) {
  Expansion out;
  for (double x : a)
    for (double y : b) {
      const double p = x * y;
      grow(out, std::fma(x, y, -p));
      grow(out, p);
    }
  return out;
}

void add(Expansion& to, const Expansion& e, double sign) {
  for (double c : e) grow(to, sign * c);
}

int sign_of(const Expansion& e) {
  for (auto it = e.rbegin(); it != e.rend(); ++it)
    if (*it != 0.0) return *it > 0.0 ? 1 : -1;
  return 0;
}

}  // namespace

int exact_orientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& d, long* fallbacks) {
  const Eigen::Vector3d u = b - a, v = c - a, w = d - a;
  const double m0 = v.y() * w.z() - v.z() * w.y(), m1 = v.z() * w.x() - v.x() * w.z(),
               m2 = v.x() * w.y() - v.y() * w.x();
  const double det = u.x() * m0 + u.y() * m1 + u.z() * m2;
  const double permanent = std::abs(u.x()) * (std::abs(v.y() * w.z()) + std::abs(v.z() * w.y())) +
                           std::abs(u.y()) * (std::abs(v.z() * w.x()) + std::abs(v.x() * w.z())) +
                           std::abs(u.z()) * (std::abs(v.x() * w.y()) + std::abs(v.y() * w.x()));
  // Shewchuk's orient3d filter bound is (7 + 56 eps) eps x permanent (eps = 2^-53, 7.8e-16);
  // 1e-15 is above it.
  if (std::abs(det) > 1e-15 * permanent) return det > 0.0 ? 1 : -1;
  if (fallbacks) ++*fallbacks;
  // Exactly: the differences as two-component expansions, the cofactor expansion in them.
  std::array<Expansion, 3> U, V, W;
  for (int k = 0; k < 3; ++k) {
    U[static_cast<std::size_t>(k)] = difference(b[k], a[k]);
    V[static_cast<std::size_t>(k)] = difference(c[k], a[k]);
    W[static_cast<std::size_t>(k)] = difference(d[k], a[k]);
  }
  Expansion total;
  for (int k = 0; k < 3; ++k) {
    const std::size_t i = static_cast<std::size_t>(k), j = static_cast<std::size_t>((k + 1) % 3),
                      l = static_cast<std::size_t>((k + 2) % 3);
    // u_k (v_j w_l - v_l w_j)
    add(total, product(U[i], product(V[j], W[l])), 1.0);
    add(total, product(U[i], product(V[l], W[j])), -1.0);
  }
  return sign_of(total);
}

namespace {

struct Triangle {
  std::array<Eigen::Vector3d, 3> p;
  Eigen::Vector3d lo, hi;
};

bool boxes_overlap(const Eigen::Vector3d& lo_a, const Eigen::Vector3d& hi_a, const Eigen::Vector3d& lo_b,
                   const Eigen::Vector3d& hi_b) {
  return (lo_a.array() <= hi_b.array()).all() && (lo_b.array() <= hi_a.array()).all();
}

// Closed segment (p, q) against closed triangle t; coplanar configurations count as meeting.
bool segment_meets_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Triangle& t, long& fallbacks) {
  const int op = exact_orientation(t.p[0], t.p[1], t.p[2], p, &fallbacks);
  const int oq = exact_orientation(t.p[0], t.p[1], t.p[2], q, &fallbacks);
  if (op == oq && op != 0) return false;
  if (op == 0 && oq == 0) return true;  // coplanar: conservative
  const int o0 = exact_orientation(p, q, t.p[0], t.p[1], &fallbacks);
  const int o1 = exact_orientation(p, q, t.p[1], t.p[2], &fallbacks);
  const int o2 = exact_orientation(p, q, t.p[2], t.p[0], &fallbacks);
  return (o0 >= 0 && o1 >= 0 && o2 >= 0) || (o0 <= 0 && o1 <= 0 && o2 <= 0);
}

bool triangles_meet(const Triangle& s, const Triangle& t, long& fallbacks) {
  for (int k = 0; k < 3; ++k) {
    if (segment_meets_triangle(s.p[static_cast<std::size_t>(k)], s.p[static_cast<std::size_t>((k + 1) % 3)], t,
                               fallbacks) ||
        segment_meets_triangle(t.p[static_cast<std::size_t>(k)], t.p[static_cast<std::size_t>((k + 1) % 3)], s,
                               fallbacks))
      return true;
  }
  return false;
}

std::vector<Triangle> world_triangles(const ElementMesh& mesh, const Eigen::Vector3d& T, const Eigen::Vector3d& w) {
  const Eigen::Matrix3d R = rigid::rotation_matrix(w);
  std::vector<Triangle> out(static_cast<std::size_t>(mesh.faces.rows()));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    Triangle& t = out[static_cast<std::size_t>(f)];
    for (int k = 0; k < 3; ++k)
      t.p[static_cast<std::size_t>(k)] = T + R * mesh.vertices.row(mesh.faces(f, k)).transpose();
    t.lo = t.p[0].cwiseMin(t.p[1]).cwiseMin(t.p[2]);
    t.hi = t.p[0].cwiseMax(t.p[1]).cwiseMax(t.p[2]);
  }
  return out;
}

}  // namespace

MeshIntersectionReport check_mesh_intersections(const PeriodicRigidCell& cell, const Vector& x) {
  if (!is_mesh_cell(cell.spec())) throw std::invalid_argument("check_mesh_intersections: not a mesh cell");
  const int nb = cell.num_bodies(), n = cell.num_elements();
  std::vector<std::vector<Triangle>> triangles;
  std::vector<Eigen::Vector3d> lo, hi;
  for (int b = 0; b < nb; ++b) {
    const ElementMesh& mesh = *cell.spec().elements[static_cast<std::size_t>(cell.master(b))].mesh;
    triangles.push_back(world_triangles(mesh, x.segment<3>(6 * b), x.segment<3>(6 * b + 3)));
    Eigen::Vector3d l = triangles.back().front().lo, h = triangles.back().front().hi;
    for (const Triangle& t : triangles.back()) {
      l = l.cwiseMin(t.lo);
      h = h.cwiseMax(t.hi);
    }
    lo.push_back(l);
    hi.push_back(h);
  }
  MeshIntersectionReport report;
  for (int a = 0; a < nb; ++a)
    for (int b = a + 1; b < nb; ++b) {
      if (a >= n && b >= n) continue;  // image-image: another cell's master-image pair
      const std::size_t ia = static_cast<std::size_t>(a), ib = static_cast<std::size_t>(b);
      if (!boxes_overlap(lo[ia], hi[ia], lo[ib], hi[ib])) continue;
      for (const Triangle& s : triangles[ia]) {
        if (!boxes_overlap(s.lo, s.hi, lo[ib], hi[ib])) continue;
        for (const Triangle& t : triangles[ib]) {
          if (!boxes_overlap(s.lo, s.hi, t.lo, t.hi)) continue;
          ++report.triangle_pairs;
          if (triangles_meet(s, t, report.exact_fallbacks)) ++report.intersecting;
        }
      }
    }
  return report;
}

}  // namespace tailor::interlocking
