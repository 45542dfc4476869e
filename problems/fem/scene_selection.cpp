#include "problems/fem/scene_selection.hpp"

#include <algorithm>
#include <set>
#include <sstream>

#include "forward/core/format_number.hpp"

namespace tailor {
namespace {

std::string format_vector(const Eigen::VectorXd& v) {
  std::ostringstream s;
  s << "[";
  for (Eigen::Index k = 0; k < v.size(); ++k) s << (k ? ", " : "") << v[k];
  s << "]";
  return s.str();
}

std::string mesh_extent(const Mesh& mesh) {
  return "the mesh spans " + format_vector(mesh.rest_positions.colwise().minCoeff().transpose()) + " to " +
         format_vector(mesh.rest_positions.colwise().maxCoeff().transpose());
}

bool inside(const Eigen::VectorXd& point, const Eigen::VectorXd& min, const Eigen::VectorXd& max,
            double tolerance) {
  return (point.array() >= min.array() - tolerance).all() && (point.array() <= max.array() + tolerance).all();
}

}  // namespace

void throw_scene_error(const Scene& scene, const std::string& key, const std::string& what) {
  throw SceneError(scene.source + ": " + key + ": " + what);
}

void check_dimension(const Scene& scene, const Mesh& mesh, const Eigen::VectorXd& v, const std::string& key) {
  if (v.size() != mesh.dim())
    throw_scene_error(scene, key,
                      "expected " + std::to_string(mesh.dim()) + " components (the mesh is " +
                          std::to_string(mesh.dim()) + "D), got " + std::to_string(v.size()));
}

double default_selection_tolerance(const Mesh& mesh) {
  const Eigen::VectorXd extent =
      mesh.rest_positions.colwise().maxCoeff() - mesh.rest_positions.colwise().minCoeff();
  return 1e-9 * extent.norm();
}

std::vector<int> select_vertices(const Scene& scene, const Mesh& mesh, const VertexSelector& selector) {
  std::vector<int> ids;
  const double tolerance = selector.tolerance >= 0 ? selector.tolerance : default_selection_tolerance(mesh);
  switch (selector.kind) {
    case VertexSelector::Kind::plane: {
      if (selector.axis >= mesh.dim())
        throw_scene_error(scene, selector.key + ".plane.axis",
                          "axis " + axis_name(selector.axis) + " does not exist in a " +
                              std::to_string(mesh.dim()) + "D mesh");
      for (int v = 0; v < mesh.num_vertices(); ++v)
        if (std::abs(mesh.rest_positions(v, selector.axis) - selector.value) <= tolerance) ids.push_back(v);
      if (ids.empty())
        throw_scene_error(scene, selector.key,
                          "selects no vertices (no vertex has " + axis_name(selector.axis) + " = " +
                              format_number(selector.value) + " within " + format_number(tolerance) + "; " +
                              mesh_extent(mesh) + ")");
      break;
    }
    case VertexSelector::Kind::box: {
      check_dimension(scene, mesh, selector.min, selector.key + ".box.min");
      for (int v = 0; v < mesh.num_vertices(); ++v)
        if (inside(mesh.rest_positions.row(v).transpose(), selector.min, selector.max, tolerance))
          ids.push_back(v);
      if (ids.empty())
        throw_scene_error(scene, selector.key,
                          "selects no vertices (none inside " + format_vector(selector.min) + " to " +
                              format_vector(selector.max) + "; " + mesh_extent(mesh) + ")");
      break;
    }
    case VertexSelector::Kind::boundary: {
      std::vector<char> on_boundary(static_cast<std::size_t>(mesh.num_vertices()), 0);
      const Eigen::MatrixXi facets = boundary_facets(mesh);
      for (Eigen::Index k = 0; k < facets.size(); ++k)
        on_boundary[static_cast<std::size_t>(facets.data()[k])] = 1;
      for (int v = 0; v < mesh.num_vertices(); ++v)
        if (on_boundary[static_cast<std::size_t>(v)]) ids.push_back(v);
      break;
    }
    case VertexSelector::Kind::list: {
      for (int v : selector.ids)
        if (v >= mesh.num_vertices())
          throw_scene_error(scene, selector.key,
                            "vertex " + std::to_string(v) + " does not exist (the mesh has " +
                                std::to_string(mesh.num_vertices()) + " vertices)");
      ids = selector.ids;
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      break;
    }
  }
  return ids;
}

std::vector<int> select_elements(const Scene& scene, const Mesh& mesh, const ElementSelector& selector) {
  std::vector<int> elements;
  switch (selector.kind) {
    case ElementSelector::Kind::all:
      for (int e = 0; e < mesh.num_elements(); ++e) elements.push_back(e);
      break;
    case ElementSelector::Kind::region: {
      for (int e = 0; e < mesh.num_elements(); ++e)
        if (mesh.element_regions.size() == mesh.num_elements() && mesh.element_regions[e] == selector.region)
          elements.push_back(e);
      if (elements.empty()) {
        std::set<int> present(mesh.element_regions.data(),
                              mesh.element_regions.data() + mesh.element_regions.size());
        std::string list;
        for (int r : present) list += (list.empty() ? "" : ", ") + std::to_string(r);
        throw_scene_error(scene, selector.key,
                          "selects no elements (no element has region " + std::to_string(selector.region) +
                              "; regions present: " + (list.empty() ? "none" : list) + ")");
      }
      break;
    }
    case ElementSelector::Kind::box: {
      check_dimension(scene, mesh, selector.min, selector.key + ".box.min");
      const double tolerance = default_selection_tolerance(mesh);
      for (int e = 0; e < mesh.num_elements(); ++e) {
        Eigen::VectorXd centroid = Eigen::VectorXd::Zero(mesh.dim());
        for (int a = 0; a < mesh.elements.cols(); ++a)
          centroid += mesh.rest_positions.row(mesh.elements(e, a)).transpose();
        centroid /= static_cast<double>(mesh.elements.cols());
        if (inside(centroid, selector.min, selector.max, tolerance)) elements.push_back(e);
      }
      if (elements.empty())
        throw_scene_error(scene, selector.key,
                          "selects no elements (no element centroid inside " + format_vector(selector.min) +
                              " to " + format_vector(selector.max) + "; " + mesh_extent(mesh) + ")");
      break;
    }
  }
  return elements;
}

Eigen::MatrixXi select_boundary_facets(const Scene& scene, const Mesh& mesh, const VertexSelector& selector) {
  const std::vector<int> ids = select_vertices(scene, mesh, selector);
  std::vector<char> selected(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (int v : ids) selected[static_cast<std::size_t>(v)] = 1;
  const Eigen::MatrixXi facets = boundary_facets(mesh);
  std::vector<int> rows;
  for (int f = 0; f < facets.rows(); ++f) {
    bool all = true;
    for (int a = 0; a < facets.cols(); ++a) all = all && selected[static_cast<std::size_t>(facets(f, a))];
    if (all) rows.push_back(f);
  }
  if (rows.empty())
    throw_scene_error(scene, selector.key,
                      "selects no boundary facets (" + std::to_string(ids.size()) +
                          " vertices selected, but no boundary facet has all its vertices among them)");
  Eigen::MatrixXi out(static_cast<Eigen::Index>(rows.size()), facets.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = facets.row(rows[k]);
  return out;
}

}  // namespace tailor
