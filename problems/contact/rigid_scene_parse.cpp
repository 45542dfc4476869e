// Parsing contact scenes into RigidSceneSpec (see rigid_scene.hpp; keys in docs/contact.md).
#include <filesystem>

#include "forward/mesh/mesh_io.hpp"
#include "problems/contact/fem_bodies.hpp"
#include "problems/contact/rigid_scene.hpp"
#include "problems/fem/scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

rigid::RigidBody parse_body(const SceneNode& node, const std::string& directory,
                            std::vector<int>& fixed_dofs) {
  node.expect_keys({"name", "primitive", "mesh", "size", "radius", "subdivisions", "density", "position",
                    "velocity", "angular_velocity", "rotation", "fixed", "fixed_dofs", "kinematic", "force",
                    "torque"});
  Eigen::MatrixX3d vertices;
  Eigen::MatrixX3i faces;
  if (node.has("mesh")) {
    // The boundary of a tetrahedral mesh file (path relative to the scene file).
    const std::filesystem::path path = std::filesystem::path(directory) / node.at("mesh").string();
    const Mesh mesh = read_mesh(path.string());
    if (mesh.dim() != 3) node.at("mesh").fail("expected a 3D tetrahedral mesh");
    std::vector<int> mesh_vertex;
    boundary_surface(mesh, faces, mesh_vertex);
    vertices.resize(static_cast<Eigen::Index>(mesh_vertex.size()), 3);
    for (std::size_t i = 0; i < mesh_vertex.size(); ++i)
      vertices.row(static_cast<Eigen::Index>(i)) = mesh.rest_positions.row(mesh_vertex[i]);
  } else {
    const std::string primitive = node.at("primitive").choice({"box", "sphere"});
    if (primitive == "box") {
      rigid::box_surface(node.at("size").vector(3), vertices, faces);
    } else {
      const int subdivisions = node.has("subdivisions") ? node.at("subdivisions").integer(0) : 2;
      if (subdivisions > 6) node.at("subdivisions").fail("at most 6 subdivisions");
      rigid::sphere_surface(node.at("radius").positive(), subdivisions, vertices, faces);
    }
  }
  const double density = node.has("density") ? node.at("density").positive() : 1000.0;
  const bool fixed = node.has("fixed") && node.at("fixed").boolean();
  rigid::RigidBody body;
  try {
    body = rigid::rigid_body_from_mesh(node.has("name") ? node.at("name").string() : "", vertices, faces,
                                       density, fixed);
  } catch (const std::invalid_argument& e) {
    node.fail(e.what());
  }
  // A primitive is placed by its centre; a mesh keeps its own coordinates unless positioned.
  if (!node.has("mesh")) body.position.setZero();
  if (node.has("position")) body.position = node.at("position").vector(3);
  if (node.has("rotation")) body.rotation = node.at("rotation").vector(3);
  if (body.rotation.norm() >= M_PI)
    node.at("rotation").fail("the rotation vector's angle must stay below pi");
  if (auto k = node.find("kinematic")) {
    k->expect_keys({"velocity", "angular_velocity"});
    if (fixed) k->fail("a body is either fixed or kinematic");
    body.kinematic = true;
    if (k->has("velocity")) body.kinematic_velocity = k->at("velocity").vector(3);
    if (k->has("angular_velocity")) body.kinematic_angular_velocity = k->at("angular_velocity").vector(3);
    for (const char* key : {"velocity", "angular_velocity", "fixed_dofs", "force", "torque"})
      if (node.has(key))
        node.at(key).fail(std::string("a kinematic body follows its prescribed motion: no ") + key +
                          " (give kinematic.velocity and kinematic.angular_velocity)");
  }
  fixed_dofs.clear();
  if (node.has("fixed_dofs"))
    for (const SceneNode& item : node.at("fixed_dofs").items()) {
      const std::string dof = item.choice({"x", "y", "z", "rx", "ry", "rz"});
      const char* names[] = {"x", "y", "z", "rx", "ry", "rz"};
      for (int k = 0; k < 6; ++k)
        if (dof == names[k]) fixed_dofs.push_back(k);
    }
  return body;
}

// contact.stiffness: a number (fixed kappa) or "adaptive" (with min_stiffness, max_stiffness).
void parse_stiffness(const SceneNode& c, RigidSceneSpec& spec) {
  spec.stiffness.adaptive = !c.has("stiffness");  // the default
  if (auto s = c.find("stiffness")) {
    if (s->is_string()) {
      if (s->string() != "adaptive")
        s->fail("expected a positive number (a fixed kappa) or \"adaptive\", got \"" + s->string() + "\"");
      spec.stiffness.adaptive = true;
    } else {
      spec.contact.stiffness = s->positive();
    }
  }
  for (const char* key : {"min_stiffness", "max_stiffness"})
    if (c.has(key) && !spec.stiffness.adaptive)
      c.at(key).fail("only with \"stiffness\": \"adaptive\" (a number fixes kappa)");
  if (auto v = c.find("min_stiffness")) spec.stiffness.min_stiffness = v->positive();
  if (auto v = c.find("max_stiffness")) spec.stiffness.max_stiffness = v->positive();
  if (spec.stiffness.min_stiffness > 0.0 && spec.stiffness.max_stiffness > 0.0 &&
      spec.stiffness.max_stiffness < spec.stiffness.min_stiffness)
    c.at("max_stiffness").fail("must be at least min_stiffness");
}

}  // namespace

bool RigidSceneSpec::has_torques() const {
  for (const Eigen::Vector3d& t : torques)
    if (t.squaredNorm() > 0.0) return true;
  return false;
}

RigidSceneSpec parse_rigid_scene(const SceneNode& root, const std::string& directory) {
  root.expect_keys(
      {"name", "description", "rigid_bodies", "fem_bodies", "gravity", "contact", "newton", "dynamics"});
  RigidSceneSpec spec;
  spec.source = root.source();
  if (root.has("name")) spec.name = root.at("name").string();
  if (root.has("description")) spec.description = root.at("description").string();
  const std::vector<SceneNode> bodies = root.at("rigid_bodies").items();
  if (bodies.empty()) root.at("rigid_bodies").fail("expected at least one body");
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    std::vector<int> fixed;
    spec.bodies.push_back(parse_body(bodies[b], directory, fixed));
    if (spec.bodies.back().name.empty()) spec.bodies.back().name = "body" + std::to_string(b);
    spec.fixed_body_dofs.push_back(fixed);
    auto vector_or_zero = [&](const char* key) {
      return bodies[b].has(key) ? Eigen::Vector3d(bodies[b].at(key).vector(3)) : Eigen::Vector3d::Zero();
    };
    spec.velocities.push_back(vector_or_zero("velocity"));
    spec.angular_velocities.push_back(vector_or_zero("angular_velocity"));
    spec.forces.push_back(vector_or_zero("force"));
    spec.torques.push_back(vector_or_zero("torque"));
  }
  if (root.has("gravity")) spec.gravity = root.at("gravity").vector(3);
  if (auto list = root.find("fem_bodies"))
    for (const SceneNode& item : list->items())
      spec.fem_bodies.push_back(parse_fem_body(item, spec.gravity, spec.source, directory));
  if (root.has("dynamics")) {
    const SceneNode d = root.at("dynamics");
    d.expect_keys({"time_step", "steps", "output_every", "velocity_tolerance", "initial_guess"});
    spec.time_step = d.at("time_step").positive();
    spec.steps = d.at("steps").integer(1);
    if (d.has("output_every")) spec.output_every = d.at("output_every").integer(1);
    if (d.has("velocity_tolerance")) spec.velocity_tolerance = d.at("velocity_tolerance").non_negative();
    if (d.has("initial_guess"))
      spec.initial_guess = d.at("initial_guess").choice({"previous", "predicted"}) == "predicted"
                               ? rigid::InitialGuess::predicted
                               : rigid::InitialGuess::previous;
    if (!spec.fem_bodies.empty())
      root.at("fem_bodies").fail("FEM bodies are supported in static scenes only (no \"dynamics\" section)");
  } else {
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      if (spec.bodies[b].kinematic)
        bodies[b]
            .at("kinematic")
            .fail("kinematic bodies need a \"dynamics\" section (their pose follows time)");
      for (const char* key : {"velocity", "angular_velocity"})
        if (bodies[b].has(key)) bodies[b].at(key).fail("initial velocities need a \"dynamics\" section");
    }
  }
  spec.stiffness.adaptive = !root.has("contact");  // no contact section: adaptive kappa
  if (root.has("contact")) {
    const SceneNode c = root.at("contact");
    c.expect_keys({"activation_distance", "stiffness", "min_stiffness", "max_stiffness", "friction",
                   "friction_velocity", "friction_iterations", "ccd_separation"});
    if (c.has("activation_distance"))
      spec.contact.activation_distance = c.at("activation_distance").positive();
    parse_stiffness(c, spec);
    if (c.has("ccd_separation"))
      spec.contact.ccd.separation_fraction = c.at("ccd_separation").open_interval(0, 1);
    if (c.has("friction")) {
      spec.friction.coefficient = c.at("friction").non_negative();
      if (spec.friction.coefficient > 0.0 && spec.time_step == 0.0)
        c.at("friction").fail("friction needs a \"dynamics\" section (static equilibrium is frictionless)");
    }
    if (c.has("friction_velocity")) spec.friction.velocity_threshold = c.at("friction_velocity").positive();
    if (c.has("friction_iterations")) spec.friction_iterations = c.at("friction_iterations").integer(1);
  }
  if (root.has("newton")) {
    const SceneNode n = root.at("newton");
    n.expect_keys({"max_iterations", "relative_tolerance"});
    if (n.has("max_iterations")) spec.newton.max_iterations = n.at("max_iterations").integer(1);
    if (n.has("relative_tolerance"))
      spec.newton.relative_tolerance = n.at("relative_tolerance").open_interval(0, 1);
  }
  return spec;
}

}  // namespace tailor
