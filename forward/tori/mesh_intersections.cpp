// Edge-face crossings between rigid bodies' meshes (see mesh_intersections.hpp).
#include "forward/tori/mesh_intersections.hpp"

#include <vector>

#include "forward/contact/intersection.hpp"

namespace tailor::tori {
namespace {

struct WorldMesh {
  Eigen::MatrixX3d x;
  Eigen::MatrixX2i edges;
  Eigen::MatrixX3d face_lo, face_hi;
  Eigen::Vector3d centre;
  double radius = 0.0;
};

int crossings(const WorldMesh& e, const WorldMesh& f, const Eigen::MatrixX3i& faces) {
  int count = 0;
  for (int k = 0; k < e.edges.rows(); ++k) {
    const Eigen::Vector3d a = e.x.row(e.edges(k, 0)).transpose(), b = e.x.row(e.edges(k, 1)).transpose();
    const Eigen::Vector3d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    if ((a - f.centre).norm() > f.radius + (b - a).norm()) continue;  // outside f's bounding sphere
    for (int t = 0; t < faces.rows(); ++t) {
      if ((hi.array() < f.face_lo.row(t).transpose().array()).any() ||
          (f.face_hi.row(t).transpose().array() < lo.array()).any())
        continue;
      if (contact::segment_intersects_triangle(a, b, f.x.row(faces(t, 0)).transpose(), f.x.row(faces(t, 1)).transpose(),
                                               f.x.row(faces(t, 2)).transpose()))
        ++count;
    }
  }
  return count;
}

}  // namespace

int count_body_intersections(const rigid::RigidBodySystem& system, const Vector& q) {
  const int n = system.num_bodies();
  std::vector<WorldMesh> meshes(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const rigid::RigidBody& body = system.body(i);
    WorldMesh& m = meshes[static_cast<std::size_t>(i)];
    const Eigen::Matrix3d Q = rigid::rotation_matrix(q.segment<3>(6 * i + 3));
    m.centre = q.segment<3>(6 * i);
    m.x = (body.vertices * Q.transpose()).rowwise() + m.centre.transpose();
    m.radius = body.vertices.rowwise().norm().maxCoeff();
    const contact::ContactSurface s = contact::ContactSurface::from_faces(static_cast<int>(body.vertices.rows()), body.faces);
    m.edges = s.edges;
    m.face_lo.resize(body.faces.rows(), 3);
    m.face_hi.resize(body.faces.rows(), 3);
    for (int t = 0; t < body.faces.rows(); ++t) {
      m.face_lo.row(t) = m.x.row(body.faces(t, 0)).cwiseMin(m.x.row(body.faces(t, 1))).cwiseMin(m.x.row(body.faces(t, 2)));
      m.face_hi.row(t) = m.x.row(body.faces(t, 0)).cwiseMax(m.x.row(body.faces(t, 1))).cwiseMax(m.x.row(body.faces(t, 2)));
    }
  }
  int count = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const WorldMesh &a = meshes[static_cast<std::size_t>(i)], &b = meshes[static_cast<std::size_t>(j)];
      if ((a.centre - b.centre).norm() > a.radius + b.radius) continue;
      count += crossings(a, b, system.body(j).faces) + crossings(b, a, system.body(i).faces);
    }
  return count;
}

}  // namespace tailor::tori
