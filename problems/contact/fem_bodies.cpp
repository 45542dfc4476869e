// FEM bodies in contact scenes (see fem_bodies.hpp).
#include "problems/contact/fem_bodies.hpp"

#include <nlohmann/json.hpp>

#include "problems/fem/scene.hpp"

namespace tailor {

void boundary_surface(const Mesh& mesh, Eigen::MatrixX3i& faces, std::vector<int>& mesh_vertex) {
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  std::vector<int> index(static_cast<std::size_t>(mesh.num_vertices()), -1);
  mesh_vertex.clear();
  faces.resize(facets.rows(), 3);
  for (int f = 0; f < facets.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int& i = index[static_cast<std::size_t>(facets(f, k))];
      if (i < 0) {
        i = static_cast<int>(mesh_vertex.size());
        mesh_vertex.push_back(facets(f, k));
      }
      faces(f, k) = i;
    }
}

FemBodySpec parse_fem_body(const SceneNode& node, const Eigen::Vector3d& gravity, const std::string& source,
                           const std::string& directory) {
  node.expect_keys({"name", "mesh", "materials", "dirichlet", "loads"});
  FemBodySpec spec;
  spec.name = node.has("name") ? node.at("name").string() : "fem" + node.path();
  nlohmann::json sub = node.json();
  sub.erase("name");
  // The scene's gravity acts on FEM bodies with a density, unless their loads give their own.
  bool has_density = false;
  for (const auto& material : sub["materials"])
    if (material.is_object() && material.contains("density") && material["density"].is_number() &&
        material["density"].get<double>() > 0.0)
      has_density = true;
  if (has_density && gravity.squaredNorm() > 0.0 &&
      !(sub.contains("loads") && sub["loads"].contains("gravity")))
    sub["loads"]["gravity"] = {gravity.x(), gravity.y(), gravity.z()};
  const std::string body_source = source + ": " + node.path();
  auto scene = std::make_shared<Scene>(parse_scene(SceneNode(sub, body_source, ""), directory));
  scene->name = spec.name;
  spec.scene = std::move(scene);
  return spec;
}

FemBodyPart build_fem_body(const FemBodySpec& spec, int dof_offset, int parameter_offset) {
  FemBodyPart part;
  part.name = spec.name;
  require_linear_elements(*spec.scene, "contact bodies");
  part.setup = setup_static_scene(*spec.scene);
  if (part.setup.dim() != 3)
    throw SceneError(spec.scene->source + ": mesh: contact scenes need a 3D (tetrahedral) mesh");
  part.model = build_static_model(part.setup, 1.0);
  part.parameters = part.setup.parameters();
  part.dof_offset = dof_offset;
  part.parameter_offset = parameter_offset;
  boundary_surface(part.setup.mesh, part.faces, part.mesh_vertex);
  return part;
}

}  // namespace tailor
