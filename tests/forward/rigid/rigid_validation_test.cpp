// Validation of rigid bodies with IPC contact in static equilibrium:
//  - a box resting on a fixed ground: the contact force on the box equals its weight and the
//    ground receives the opposite force (statics: equilibrium of forces, Newton's third law);
//    the resting box stays level (symmetry);
//  - a fixed sphere squeezed between two walls pushed with growing forces: each wall's
//    contact force equals its load and the surfaces never intersect (IPC's guarantee, Li et
//    al. 2020), checked by exact distances over all pairs;
//  - the static adjoint through active contact: a Taylor test of the box height with
//    respect to the masses (remainder rates ~1 without and ~2 with the gradient).
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/core/model.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_load_term.hpp"
#include "forward/solve/newton.hpp"
#include "objectives/target_positions.hpp"
#include "rigid_scenes.hpp"

namespace tailor::rigid::rigid_validation_test {
namespace {

constexpr double kGravity = 9.81;

// The smallest distance over all admissible pairs (exact distances, no broad phase).
double exact_min_distance(const RigidBodySystem& system, const Vector& q) {
  const contact::Positions x = system.world_positions(q);
  const contact::ContactSurface& s = system.surface();
  auto p = [&](int v) -> contact::Point { return x.row(v).transpose(); };
  double best = std::numeric_limits<double>::infinity();
  for (int v = 0; v < s.num_vertices; ++v)
    for (int f = 0; f < s.faces.rows(); ++f)
      if (contact::admissible_point_triangle(s, v, f))
        best = std::min(
            best, contact::classify_point_triangle(p(v), p(s.faces(f, 0)), p(s.faces(f, 1)), p(s.faces(f, 2)))
                      .squared_distance);
  for (int a = 0; a < s.edges.rows(); ++a)
    for (int b = a + 1; b < s.edges.rows(); ++b)
      if (contact::admissible_edge_edge(s, a, b))
        best = std::min(best, contact::classify_edge_edge(p(s.edges(a, 0)), p(s.edges(a, 1)),
                                                          p(s.edges(b, 0)), p(s.edges(b, 1)))
                                  .squared_distance);
  return std::sqrt(best);
}

contact::ContactOptions contact_options(double d_hat, double kappa) {
  contact::ContactOptions o;
  o.activation_distance = d_hat;
  o.stiffness = kappa;
  return o;
}

// Box (1 m, 1 kg) on a fixed ground (4 m unless given); the box's lateral translation and spin about z are
// fixed (frictionless contact gives them no stiffness). d_hat = 1 cm.
struct BoxOnGround {
  RigidBodySystem system;
  Model model{system.num_dofs()};
  RigidContactTerm* contact = nullptr;
  explicit BoxOnGround(int mass_offset = -1, const Eigen::Vector3d& ground = Eigen::Vector3d(4, 4, 1),
                       const Eigen::Vector2d& offset = Eigen::Vector2d::Zero())
      : system(testing::box_on_ground(ground, Eigen::Vector3d(1, 1, 1), 0.005, offset,
                                      Eigen::Vector3d::Zero())) {
    if (mass_offset >= 0) model.parameter_layout().add("mass", 2);
    model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -kGravity), mass_offset));
    contact = &model.add(std::make_unique<RigidContactTerm>(system, contact_options(0.01, 1e5)));
    std::vector<int> fixed = system.fixed_dofs();
    for (int dof : {6, 7, 11}) fixed.push_back(dof);
    model.set_elimination(Elimination::dirichlet(fixed, system.initial_state()));
  }
};

TEST(RigidValidation, BoxRestingOnGroundContactForceEqualsWeight) {
  BoxOnGround scene;
  const double mass = scene.system.body(1).mass;
  EXPECT_NEAR(mass, 1.0, 1e-12);
  NewtonSolver newton(scene.model);
  Vector y = scene.model.elimination().restrict_state(scene.system.initial_state());
  const NewtonResult result = newton.solve(Vector(), y);
  ASSERT_TRUE(result.converged()) << result.report();
  const Vector q = scene.model.state(y, Vector());
  Vector contact_gradient = Vector::Zero(q.size());
  scene.contact->add_gradient(q, Vector(), contact_gradient);
  const Eigen::Vector3d on_box = -contact_gradient.segment<3>(6), on_ground = -contact_gradient.segment<3>(0);
  std::printf(
      "box on ground: %d Newton iterations, contact force on box %.12g N (weight %.12g N), gap %.4g m\n",
      result.iterations, on_box.z(), mass * kGravity, scene.contact->min_distance(q, 1.0));
  EXPECT_NEAR(on_box.z(), mass * kGravity, 1e-8 * mass * kGravity);
  EXPECT_LT(on_box.head<2>().norm(), 1e-9);
  EXPECT_LT((on_ground + on_box).norm(), 1e-9 * mass * kGravity);
  EXPECT_LT(q.segment<3>(9).norm(), 1e-9);  // level
  const double gap = scene.contact->min_distance(q, 1.0);
  EXPECT_GT(gap, 0.0);
  EXPECT_LT(gap, 0.01);
}

TEST(RigidValidation, SphereSqueezedBetweenWallsNeverIntersects) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  sphere_surface(0.5, 2, v, f);
  RigidBody sphere = rigid_body_from_mesh("sphere", v, f, 1.0, true);
  const double reach = v.col(0).maxCoeff();  // the sphere mesh's extent along x
  box_surface(Eigen::Vector3d(0.2, 2, 2), v, f);
  const double d_hat = 0.01;
  RigidBody left = rigid_body_from_mesh("left", v, f, 1.0), right = left;
  left.position = Eigen::Vector3d(-(reach + 0.1 + 0.5 * d_hat), 0, 0);
  right.position = Eigen::Vector3d(reach + 0.1 + 0.5 * d_hat, 0, 0);
  const RigidBodySystem system({sphere, left, right});
  Model model(system.num_dofs());
  const RigidContactTerm& contact =
      model.add(std::make_unique<RigidContactTerm>(system, contact_options(d_hat, 1e3)));
  RigidLoadTerm& load = model.add(std::make_unique<RigidLoadTerm>(Vector::Zero(18), system.initial_state()));
  std::vector<int> fixed = system.fixed_dofs();
  for (int dof : {7, 8, 9, 10, 11, 13, 14, 15, 16, 17}) fixed.push_back(dof);  // walls move along x only
  model.set_elimination(Elimination::dirichlet(fixed, system.initial_state()));
  NewtonSolver newton(model);
  Vector y = model.elimination().restrict_state(system.initial_state());
  double previous_gap = d_hat;
  for (double force : {1.0, 10.0, 100.0, 1e3, 1e4}) {
    Vector loads = Vector::Zero(18);
    loads[6] = force;    // left wall pushed to +x
    loads[12] = -force;  // right wall pushed to -x
    load.set_loads(loads);
    const NewtonResult result = newton.solve(Vector(), y);
    ASSERT_TRUE(result.converged()) << force << "\n" << result.report();
    const Vector q = model.state(y, Vector());
    Vector gradient = Vector::Zero(18);
    contact.add_gradient(q, Vector(), gradient);
    const double gap = exact_min_distance(system, q);
    std::printf("squeeze %8.0f N: %2d Newton iterations, wall contact force %.10g N, min distance %.4g m\n",
                force, result.iterations, -gradient[6], gap);
    EXPECT_NEAR(-gradient[6], -force, 1e-7 * force);
    EXPECT_NEAR(-gradient[12], force, 1e-7 * force);
    EXPECT_GT(gap, 0.0);
    EXPECT_LT(gap, previous_gap);
    previous_gap = gap;
  }
}

void taylor_test_box_height(BoxOnGround& scene, bool expect_mollified) {
  // J = 1/2 |T_box - t|^2 with T_box the DOFs 6..8 ("vertex" 2 of the 3-blocks of q).
  Matrix target(1, 3);
  target << 0.0, 0.0, 0.49;
  auto objective = std::make_shared<TargetPositions>(3, std::vector<int>{2}, target);
  StaticFunctional functional(scene.model, identity_map(2), objective,
                              scene.model.elimination().restrict_state(scene.system.initial_state()));
  Vector z(2);
  z << 5.0, 1.0;
  TaylorTestOptions options;
  options.initial_step = 0.05;
  const TaylorTestResult t = taylor_test(functional, z, options);
  std::printf("%s", t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9);
  EXPECT_NEAR(t.rate0, 1.0, 0.2);
  // Which pairs were active at the last equilibrium.
  int mollified = 0, pairs = 0;
  scene.contact->potential().for_each_active(scene.system.world_positions(functional.state()), true,
                                             [&](const contact::ActivePair& pair) {
                                               ++pairs;
                                               if (pair.derivatives.mollified) ++mollified;
                                             });
  std::printf("active pairs at the equilibrium: %d, mollified edge-edge: %d\n", pairs, mollified);
  EXPECT_GT(pairs, 0);
  EXPECT_EQ(mollified > 0, expect_mollified);  // the Taylor test covered a mollified pair
}

// The box's bottom diagonal lies parallel to the ground's top diagonal (both triangulate
// their square the same way), so a mollified edge-edge pair is active along with the
// point-triangle pairs of the corners.
TEST(RigidValidation, StaticAdjointThroughActiveContactPassesTaylorTest) {
  BoxOnGround scene(0);
  taylor_test_box_height(scene, true);
}

}  // namespace
}  // namespace tailor::rigid::rigid_validation_test
