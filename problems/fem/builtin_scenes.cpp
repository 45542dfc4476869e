#include "problems/fem/builtin_scenes.hpp"

namespace tailor {
namespace {

VertexSelector plane(int axis, double value, const std::string& key) {
  VertexSelector s;
  s.kind = VertexSelector::Kind::plane;
  s.axis = axis;
  s.value = value;
  s.key = key;
  return s;
}

}  // namespace

Scene builtin_cantilever() {
  Scene scene;
  scene.name = "cantilever";
  scene.source = "built-in cantilever";
  scene.mesh.kind = MeshSpec::Kind::box;
  scene.mesh.min = Eigen::VectorXd::Zero(3);
  scene.mesh.max.resize(3);
  scene.mesh.max << 10.0, 1.0, 1.0;
  scene.mesh.cells.resize(3);
  scene.mesh.cells << 30, 3, 3;

  MaterialSpec rubber;
  rubber.key = "materials[0]";
  rubber.elements.key = "materials[0].elements";  // kind: all
  rubber.model = MaterialKind::neo_hookean;
  rubber.youngs_modulus = 1e6;
  rubber.poisson_ratio = 0.3;
  rubber.density = 1000.0;
  scene.materials.push_back(rubber);

  DirichletSpec clamp;
  clamp.key = "dirichlet[0]";
  clamp.vertices = plane(0, 0.0, "dirichlet[0].vertices");
  scene.dirichlet.push_back(clamp);

  TractionSpec tip;
  tip.key = "loads.tractions[0]";
  tip.faces = plane(0, 10.0, "loads.tractions[0].faces");
  tip.traction.resize(3);
  tip.traction << 0.0, 0.0, -300.0;
  scene.loads.tractions.push_back(tip);

  scene.solver.newton.max_iterations = 50;
  return scene;
}

}  // namespace tailor
