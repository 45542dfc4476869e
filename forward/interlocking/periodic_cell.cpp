// The periodic rigid cell (see periodic_cell.hpp).
#include "forward/interlocking/periodic_cell.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "forward/contact/barrier_stiffness.hpp"
#include "forward/interlocking/periodic_mesh_contact.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/torus.hpp"
#include "forward/tori/torus_distance.hpp"

namespace tailor::interlocking {
namespace {

// The shifts of half the lattice within K rings (see periodic_cell.hpp).
std::vector<Eigen::Vector2i> half_shifts(int rings) {
  std::vector<Eigen::Vector2i> out;
  for (int a = 0; a <= rings; ++a)
    for (int b = -rings; b <= rings; ++b)
      if (a > 0 || b > 0) out.emplace_back(a, b);
  return out;
}

Eigen::Vector3d in_plane(const Eigen::Vector2d& v) { return {v.x(), v.y(), 0.0}; }

}  // namespace

void validate_cell(const RigidCellSpec& spec) {
  const int n = static_cast<int>(spec.elements.size());
  if (n == 0) throw std::invalid_argument("periodic cell: no elements");
  if (!spec.lattice.allFinite() || !(std::abs(spec.lattice.determinant()) > 0.0))
    throw std::invalid_argument("periodic cell: the lattice vectors are not independent");
  for (const CellElement& e : spec.elements)
    if ((e.mesh != nullptr) != is_mesh_cell(spec))
      throw std::invalid_argument("periodic cell: the elements must be all meshes or all implicit tori");
  if (is_mesh_cell(spec) && spec.bending_patch)
    throw std::invalid_argument("bending patch: mesh elements are supported in periodic cells only");
  if (spec.bending_patch) {
    int rim = 0;
    for (const CellElement& e : spec.elements) rim += e.rim;
    if (rim == 0 || rim == n)
      throw std::invalid_argument("bending patch: needs both rim (prescribed) and free elements");
    if (!spec.broad_phase) throw std::invalid_argument("bending patch: needs broad_phase");
    for (int i = 0; i < n; ++i) {
      const CellElement& e = spec.elements[static_cast<std::size_t>(i)];
      tori::validate_shape(e.shape, "bending patch: element " + std::to_string(i));
      if (!e.position.allFinite() || !e.rotation.allFinite())
        throw std::invalid_argument("bending patch: element " + std::to_string(i) + " has a non-finite placement");
    }
    if (spec.activation_distance < 0.0 || !std::isfinite(spec.activation_distance))
      throw std::invalid_argument("bending patch: activation_distance must be >= 0");
    return;
  }
  for (const CellElement& e : spec.elements)
    if (e.rim) throw std::invalid_argument("periodic cell: rim elements belong to bending patches");
  if (spec.image_rings < 1) throw std::invalid_argument("periodic cell: image_rings must be >= 1");
  if (spec.anchor < 0 || spec.anchor >= n)
    throw std::invalid_argument("periodic cell: anchor " + std::to_string(spec.anchor) + " is not an element");
  if (spec.activation_distance < 0.0 || !std::isfinite(spec.activation_distance))
    throw std::invalid_argument("periodic cell: activation_distance must be >= 0");
  double reach = 0.0;
  for (int i = 0; i < n; ++i) {
    const CellElement& e = spec.elements[static_cast<std::size_t>(i)];
    if (e.mesh)
      validate_element_mesh(*e.mesh, "periodic cell: element " + std::to_string(i));
    else
      tori::validate_shape(e.shape, "periodic cell: element " + std::to_string(i));
    if (!e.position.allFinite() || !e.rotation.allFinite())
      throw std::invalid_argument("periodic cell: element " + std::to_string(i) + " has a non-finite placement");
    reach = std::max(reach, e.mesh ? mesh_bounding_radius(*e.mesh) : tori::bounding_radius(e.shape));
  }
  // Shifts in ring K + 1 must stay out of reach: every pair of bounding spheres at least
  // reach_margin of the shortest lattice vector apart.
  const double shortest = std::min(spec.lattice.col(0).norm(), spec.lattice.col(1).norm());
  const int K = spec.image_rings + 1;
  for (int a = -K; a <= K; ++a)
    for (int b = -K; b <= K; ++b) {
      if (std::max(std::abs(a), std::abs(b)) != K) continue;
      const Eigen::Vector3d t = in_plane(spec.lattice * Eigen::Vector2d(a, b));
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double gap = (spec.elements[static_cast<std::size_t>(j)].position + t -
                              spec.elements[static_cast<std::size_t>(i)].position)
                                 .norm() -
                             2.0 * reach;
          if (gap < spec.reach_margin * shortest)
            throw std::invalid_argument("periodic cell: images " + std::to_string(K) +
                                        " cells away come within reach; raise image_rings");
        }
    }
}

PeriodicRigidCell::PeriodicRigidCell(RigidCellSpec spec) : spec_(std::move(spec)) {
  validate_cell(spec_);
  const int n = num_elements();
  double min_major = spec_.elements.front().shape.major_radius;
  for (const CellElement& e : spec_.elements) min_major = std::min(min_major, e.shape.major_radius);
  if (is_mesh_cell(spec_)) {  // meshes: the default d_hat follows the smallest mesh radius
    min_major = mesh_bounding_radius(*spec_.elements.front().mesh);
    for (const CellElement& e : spec_.elements) min_major = std::min(min_major, mesh_bounding_radius(*e.mesh));
  }
  d_hat_ = spec_.activation_distance > 0.0 ? spec_.activation_distance : 1e-3 * min_major;

  const std::vector<Eigen::Vector2i> shifts =
      spec_.bending_patch ? std::vector<Eigen::Vector2i>{} : half_shifts(spec_.image_rings);
  for (int i = 0; i < n; ++i) {
    master_.push_back(i);
    shift_.emplace_back(0, 0);
  }
  for (const Eigen::Vector2i& k : shifts)
    for (int i = 0; i < n; ++i) {
      master_.push_back(i);
      shift_.push_back(k);
    }

  // S: every body's six rows follow its master's free DOFs (the anchor's translation is none).
  std::vector<int> free_column(static_cast<std::size_t>(6 * n), -1);
  int columns = 0;
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 6; ++c)
      if (spec_.bending_patch ? !spec_.elements[static_cast<std::size_t>(i)].rim : !(i == spec_.anchor && c < 3))
        free_column[static_cast<std::size_t>(6 * i + c)] = columns++;
  Triplets triplets;
  for (int body = 0; body < num_bodies(); ++body)
    for (int c = 0; c < 6; ++c) {
      const int col = free_column[static_cast<std::size_t>(6 * master(body) + c)];
      if (col >= 0) triplets.emplace_back(6 * body + c, col, 1.0);
    }
  basis_.resize(6 * num_bodies(), columns);
  basis_.setFromTriplets(triplets.begin(), triplets.end());

  if (is_mesh_cell(spec_)) {
    build_mesh_contact();
    return;
  }
  std::vector<rigid::RigidBody> bodies;
  std::vector<tori::TorusShape> shapes;
  const Vector x = offset(Eigen::Matrix2d::Identity()) + basis_ * rest_free_state();
  for (int body = 0; body < num_bodies(); ++body) {
    const CellElement& e = spec_.elements[static_cast<std::size_t>(master(body))];
    // Images are "fixed" for the contact term only: it then skips image-image pairs.
    bodies.push_back(tori::torus_body("element_" + std::to_string(body), e.shape, 1.0, x.segment<3>(6 * body),
                                      x.segment<3>(6 * body + 3), body >= n || e.rim, 8, 4, false));
    shapes.push_back(e.shape);
    bounding_.push_back(tori::bounding_radius(e.shape));
  }
  system_ = std::make_unique<rigid::RigidBodySystem>(std::move(bodies));
  tori::TorusContactOptions options;
  options.activation_distance = d_hat_;
  options.stiffness = contact::stiffness_for_force(1.0, d_hat_);
  options.parameter_offset = 0;
  contact_ = std::make_unique<tori::TorusContactTerm>(*system_, std::move(shapes), options);

  // Overlap at rest is an input error: the barrier would be infinite.
  const double closest = contact_->min_distance(x, radii_parameters(), d_hat_);
  if (!(closest > 0.0))
    throw std::invalid_argument("periodic cell: elements overlap at rest (distance " + std::to_string(closest) + ")");
}

Elimination PeriodicRigidCell::elimination(const Eigen::Matrix2d& F) const { return Elimination(offset(F), basis_); }

Eigen::Matrix2d PeriodicRigidCell::curvature(const Eigen::Matrix2d& F) {
  return 0.5 * (F + F.transpose()) - Eigen::Matrix2d::Identity();
}

void PeriodicRigidCell::surface_pose(const Eigen::Matrix2d& K, const Eigen::Vector3d& position,
                                     const Eigen::Vector3d& rotation, Eigen::Vector3d& T, Eigen::Vector3d& w) {
  const Eigen::Vector2d p = position.head<2>(), grad = K * p;
  const Eigen::Vector3d n = Eigen::Vector3d(-grad.x(), -grad.y(), 1.0).normalized();
  // The smallest rotation taking e_z to n: about e_z x n by the angle between them.
  const Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(n);
  const double sine = axis.norm(), cosine = n.z();
  const Eigen::Vector3d q = sine > 0.0 ? Eigen::Vector3d(axis / sine * std::atan2(sine, cosine)) : Eigen::Vector3d::Zero();
  T = Eigen::Vector3d(p.x(), p.y(), 0.5 * p.dot(K * p)) + position.z() * n;
  w = rigid::rotation_vector(rigid::rotation_matrix(q) * rigid::rotation_matrix(rotation), rotation);
}

void PeriodicRigidCell::surface_pose_derivative(const Eigen::Matrix2d& K, const Eigen::Matrix2d& dK,
                                                const Eigen::Vector3d& position, const Eigen::Vector3d& rotation,
                                                Eigen::Vector3d& dT, Eigen::Vector3d& dw) {
  const Eigen::Vector2d p = position.head<2>(), grad = K * p, dgrad = dK * p;
  const Eigen::Vector3d m(-grad.x(), -grad.y(), 1.0), dm(-dgrad.x(), -dgrad.y(), 0.0);
  const Eigen::Vector3d n = m.normalized();
  const Eigen::Vector3d dn = (dm - n * n.dot(dm)) / m.norm();
  dT = Eigen::Vector3d(0.0, 0.0, 0.5 * p.dot(dK * p)) + position.z() * dn;
  // Q = I + [v] + [v]^2 / (1 + c), v = e_z x n, c = n_z (n_z > 0 on a graph surface).
  const Eigen::Vector3d v = Eigen::Vector3d::UnitZ().cross(n), dv = Eigen::Vector3d::UnitZ().cross(dn);
  const double c = n.z(), dc = dn.z();
  const Eigen::Matrix3d V = rigid::cross_matrix(v), dV = rigid::cross_matrix(dv);
  const Eigen::Matrix3d Q = Eigen::Matrix3d::Identity() + V + V * V / (1.0 + c);
  const Eigen::Matrix3d dQ = dV + (dV * V + V * dV) / (1.0 + c) - V * V * (dc / ((1.0 + c) * (1.0 + c)));
  const Eigen::Matrix3d R0 = rigid::rotation_matrix(rotation);
  const Eigen::Matrix3d R = Q * R0;
  const Eigen::Vector3d omega = rigid::skew_vee(dQ * R0 * R.transpose());  // dR R^T = [omega]
  // w = log(R) near the rest rotation (as surface_pose); dR/dw_k R^T = [J_k].
  const rigid::RotationDerivatives d = rigid::rotation_derivatives(rigid::rotation_vector(R, rotation));
  std::array<Eigen::Vector3d, 3> J;  // columns
  for (std::size_t k = 0; k < 3; ++k) J[k] = rigid::skew_vee(d.first[k] * d.rotation.transpose());
  // J^-1 omega by Cramer's rule (the rows of J^-1 are the columns' cross products over det J).
  const double det = J[0].dot(J[1].cross(J[2]));
  dw = Eigen::Vector3d(J[1].cross(J[2]).dot(omega), J[2].cross(J[0]).dot(omega), J[0].cross(J[1]).dot(omega)) / det;
}

Vector PeriodicRigidCell::offset_derivative(const Eigen::Matrix2d& F, const Eigen::Matrix2d& dF) const {
  Vector dx0 = Vector::Zero(6 * num_bodies());
  if (spec_.bending_patch) {
    const Eigen::Matrix2d K = curvature(F), dK = 0.5 * (dF + dF.transpose());
    for (int i = 0; i < num_elements(); ++i) {
      const CellElement& e = spec_.elements[static_cast<std::size_t>(i)];
      if (!e.rim) continue;
      Eigen::Vector3d dT, dw;
      surface_pose_derivative(K, dK, e.position, e.rotation, dT, dw);
      dx0.segment<3>(6 * i) = dT;
      dx0.segment<3>(6 * i + 3) = dw;
    }
    return dx0;
  }
  for (int k = 0; k < 2; ++k)
    for (int l = 0; l < 2; ++l)
      if (dF(k, l) != 0.0) dx0 += dF(k, l) * state_derivative_macro(k, l);
  return dx0;
}

Vector PeriodicRigidCell::offset(const Eigen::Matrix2d& F) const {
  Vector x0 = Vector::Zero(6 * num_bodies());
  if (spec_.bending_patch) {
    const Eigen::Matrix2d K = curvature(F);
    for (int i = 0; i < num_elements(); ++i) {
      const CellElement& e = spec_.elements[static_cast<std::size_t>(i)];
      if (!e.rim) continue;
      Eigen::Vector3d T, w;
      surface_pose(K, e.position, e.rotation, T, w);
      x0.segment<3>(6 * i) = T;
      x0.segment<3>(6 * i + 3) = w;
    }
    return x0;
  }
  const Eigen::Vector3d anchor = spec_.elements[static_cast<std::size_t>(spec_.anchor)].position;
  for (int body = 0; body < num_bodies(); ++body) {
    const Eigen::Vector2d t = F * (spec_.lattice * shift(body).cast<double>());
    x0.segment<3>(6 * body) = in_plane(t);
    if (master(body) == spec_.anchor) x0.segment<3>(6 * body) += anchor;
  }
  return x0;
}

Vector PeriodicRigidCell::full_state(const Vector& y, const Eigen::Matrix2d& F) const {
  return offset(F) + basis_ * y;
}

Vector PeriodicRigidCell::rest_free_state() const {
  Vector q(6 * num_elements());
  for (int i = 0; i < num_elements(); ++i) {
    q.segment<3>(6 * i) = spec_.elements[static_cast<std::size_t>(i)].position;
    q.segment<3>(6 * i + 3) = spec_.elements[static_cast<std::size_t>(i)].rotation;
  }
  // The master rows of S select y; the anchor's translation rows are empty.
  return basis_.topRows(6 * num_elements()).transpose() * q;
}

Vector PeriodicRigidCell::master_state(const Vector& y) const {
  return full_state(y, Eigen::Matrix2d::Identity()).head(6 * num_elements());
}

Vector PeriodicRigidCell::state_derivative_macro(int k, int l) const {
  Vector dx = Vector::Zero(6 * num_bodies());
  for (int body = 0; body < num_bodies(); ++body)
    dx[6 * body + k] = (spec_.lattice * shift(body).cast<double>())[l];
  return dx;
}

Vector PeriodicRigidCell::state_derivative_lattice(const Eigen::Matrix2d& F, int k, int l) const {
  Vector dx = Vector::Zero(6 * num_bodies());
  for (int body = 0; body < num_bodies(); ++body) {
    const double s = shift(body).cast<double>()[l];
    dx.segment<2>(6 * body) = F.col(k) * s;
  }
  return dx;
}

Vector PeriodicRigidCell::radii_parameters() const {
  Vector p(2 * num_bodies());
  for (int body = 0; body < num_bodies(); ++body) {
    const tori::TorusShape& s = spec_.elements[static_cast<std::size_t>(master(body))].shape;
    p[2 * body] = s.major_radius;
    p[2 * body + 1] = s.minor_radius;
  }
  return p;
}

SparseMatrix PeriodicRigidCell::radii_map() const {
  Triplets t;
  for (int body = 0; body < num_bodies(); ++body) {
    t.emplace_back(2 * body, 2 * master(body), 1.0);
    t.emplace_back(2 * body + 1, 2 * master(body) + 1, 1.0);
  }
  SparseMatrix P(2 * num_bodies(), 2 * num_elements());
  P.setFromTriplets(t.begin(), t.end());
  return P;
}

std::string PeriodicRigidCell::pair_label(int a, int b) const {
  const Eigen::Vector2i k = shift(b) - shift(a);
  return std::to_string(master(a)) + "-" + std::to_string(master(b)) + "(" + std::to_string(k.x()) + "," +
         std::to_string(k.y()) + ")";
}

std::vector<std::pair<int, int>> PeriodicRigidCell::candidate_pairs(const Vector& x, double range,
                                                                    const Vector* dx) const {
  const int nb = num_bodies(), n = num_elements();
  // Grown radii; the relative slack keeps pairs on the boundary of the exact tests (which sum
  // the radii in another order) among the candidates.
  std::vector<double> radius(static_cast<std::size_t>(nb));
  double widest = 0.0;
  for (int b = 0; b < nb; ++b) {
    double r = bounding_[static_cast<std::size_t>(b)];
    if (dx) r += dx->segment<3>(6 * b).norm();
    radius[static_cast<std::size_t>(b)] = r * (1.0 + 1e-12);
    widest = std::max(widest, r);
  }
  const double h = (2.0 * widest + range) * (1.0 + 1e-12);
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("candidate_pairs: range must be finite and >= 0");
  // Bodies sorted by grid cell; two spheres within range have centres at most h apart, so they
  // sit in the same or adjacent cells (per axis).
  struct Entry {
    std::array<long, 3> cell;
    int body;
  };
  std::vector<Entry> grid(static_cast<std::size_t>(nb));
  std::vector<std::pair<int, int>> out;
  for (int b = 0; b < nb; ++b) {
    Entry& e = grid[static_cast<std::size_t>(b)];
    for (int k = 0; k < 3; ++k) {
      const double cell = std::floor(x[6 * b + k] / h);
      if (!(std::abs(cell) < 1e15)) {
        // A position the grid cannot index (not finite, e.g. an optimizer's failed trial, or
        // beyond a long): every pair is a candidate, so the exact tests see it as all pairs do.
        for (int a = 0; a < nb; ++a)
          for (int c = a + 1; c < nb; ++c)
            if (a < n || c < n) out.emplace_back(a, c);
        return out;
      }
      e.cell[static_cast<std::size_t>(k)] = static_cast<long>(cell);
    }
    e.body = b;
  }
  const auto less = [](const Entry& u, const Entry& v) { return u.cell < v.cell; };
  std::sort(grid.begin(), grid.end(), less);
  for (int a = 0; a < nb; ++a) {
    const Entry& ea = grid[static_cast<std::size_t>(a)];
    const Eigen::Vector3d Ta = x.segment<3>(6 * ea.body);
    Entry key = ea;
    for (long i = -1; i <= 1; ++i)
      for (long j = -1; j <= 1; ++j)
        for (long k = -1; k <= 1; ++k) {
          key.cell = {ea.cell[0] + i, ea.cell[1] + j, ea.cell[2] + k};
          for (auto it = std::lower_bound(grid.begin(), grid.end(), key, less);
               it != grid.end() && it->cell == key.cell; ++it) {
            const int b = it->body;
            if (b <= ea.body || (ea.body >= n && b >= n)) continue;  // image-image (patches: none)
            const double reach = radius[static_cast<std::size_t>(ea.body)] + radius[static_cast<std::size_t>(b)] + range;
            if ((x.segment<3>(6 * b) - Ta).norm() <= reach) out.emplace_back(ea.body, b);
          }
        }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Mesh bodies: the IPC barrier on their triangles over masters and images (periodic_mesh_contact.hpp);
// an intersecting rest placement is an input error (distances alone miss an edge through a face).
void PeriodicRigidCell::build_mesh_contact() {
  std::vector<std::shared_ptr<const ElementMesh>> meshes;
  for (int body = 0; body < num_bodies(); ++body) {
    meshes.push_back(spec_.elements[static_cast<std::size_t>(master(body))].mesh);
    bounding_.push_back(mesh_bounding_radius(*meshes.back()));
  }
  const Vector x = offset(Eigen::Matrix2d::Identity()) + basis_ * rest_free_state();
  // Images whose bounding spheres stay reach_margin x the shortest lattice vector away from every
  // master's at rest never take part (the same room for strains as validate_cell's ring K + 1).
  const double room = spec_.reach_margin * std::min(spec_.lattice.col(0).norm(), spec_.lattice.col(1).norm());
  std::vector<bool> in_reach(static_cast<std::size_t>(num_bodies()), false);
  for (int body = 0; body < num_bodies(); ++body)
    for (int i = 0; i < num_elements() && !in_reach[static_cast<std::size_t>(body)]; ++i)
      in_reach[static_cast<std::size_t>(body)] =
          body < num_elements() || (x.segment<3>(6 * body) - x.segment<3>(6 * i)).norm() <
                                       bounding_[static_cast<std::size_t>(body)] + bounding_[static_cast<std::size_t>(i)] + room;
  mesh_contact_ = std::make_shared<const PeriodicMeshContact>(meshes, num_elements(), x, in_reach, d_hat_);
  const MeshIntersectionReport crossing = check_mesh_intersections(*this, x);
  const double closest = mesh_contact_->min_distance(x, d_hat_);
  if (!crossing.apart() || !(closest > 0.0))
    throw std::invalid_argument("periodic cell: mesh elements intersect at rest (" +
                                std::to_string(crossing.intersecting) + " crossing triangle pairs, distance " +
                                std::to_string(closest) + ")");
}

}  // namespace tailor::interlocking
