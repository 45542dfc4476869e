#include "forward/rig/two_bone_arm.hpp"

#include <algorithm>
#include <stdexcept>

#include "forward/mesh/generate.hpp"

namespace tailor {

Eigen::Vector2d two_bone_arm_weights(double x, const TwoBoneArmOptions& options) {
  const double s = std::clamp((x - (0.5 * options.length - options.blend)) / (2.0 * options.blend), 0.0, 1.0);
  const double forearm = s * s * (3.0 - 2.0 * s);
  return {1.0 - forearm, forearm};
}

TwoBoneArm two_bone_arm(const TwoBoneArmOptions& o) {
  if (!(o.length > 0.0) || !(o.half_width > 0.0) || o.cells_along < 2 || o.cells_across < 1 || !(o.blend > 0.0))
    throw std::invalid_argument("two-bone arm: sizes must be positive (at least 2 cells along)");
  TwoBoneArm arm;
  RiggedBody& body = arm.body;
  body.mesh = box_tet_mesh(Eigen::Vector3d(0.0, -o.half_width, -o.half_width),
                           Eigen::Vector3d(o.length, o.half_width, o.half_width), o.cells_along, o.cells_across,
                           o.cells_across);
  body.material = o.material;
  const int ne = body.mesh.num_elements(), nv = body.mesh.num_vertices();
  body.youngs_modulus = Vector::Constant(ne, o.youngs_modulus);
  body.poisson_ratio = Vector::Constant(ne, o.poisson_ratio);
  body.density = Vector::Constant(ne, o.density);
  for (int e = 0; e < ne; ++e) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) centroid += body.mesh.rest_positions.row(body.mesh.elements(e, a)).transpose() / 4.0;
    if (centroid.x() < 0.5 * o.length && centroid.y() < 0.0) {
      body.youngs_modulus[e] *= o.belly_softness;
      body.mesh.element_regions[e] = 1;
    }
  }
  arm.weights.resize(nv, 2);
  for (int v = 0; v < nv; ++v) {
    arm.weights.row(v) = two_bone_arm_weights(body.mesh.rest_positions(v, 0), o).transpose();
    if (body.mesh.rest_positions(v, 1) >= o.half_width - 1e-12) body.fixed_vertices.push_back(v);
  }
  Bone upper{"upper_arm", -1, Eigen::Vector3d::Zero(), {BoneDof{BoneDofType::rotation, Eigen::Vector3d::UnitZ()}}};
  Bone fore{"forearm", 0, Eigen::Vector3d(0.5 * o.length, -o.half_width, 0.0),
            {BoneDof{BoneDofType::rotation, Eigen::Vector3d::UnitZ()}}};
  arm.bones = {upper, fore};
  return arm;
}

}  // namespace tailor
