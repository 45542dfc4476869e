#include "problems/homogenization/rod_network_scene.hpp"

#include <Eigen/LU>
#include <climits>
#include <stdexcept>

#include "problems/scene_node.hpp"

namespace tailor {

RodNetworkScene parse_rod_network_scene(const SceneNode& section) {
  section.expect_keys({"pattern", "bar_length", "lattice", "joints", "bars", "radius", "youngs_modulus",
                       "shear_modulus", "poisson_ratio", "edges_per_bar", "depth"});
  RodNetworkScene scene;
  const double E = section.at("youngs_modulus").positive();
  const double radius = section.at("radius").positive();
  if (section.has("shear_modulus") == section.has("poisson_ratio"))
    section.fail("give exactly one of \"shear_modulus\" and \"poisson_ratio\"");
  const double G = section.has("shear_modulus")
                       ? section.at("shear_modulus").positive()
                       : E / (2.0 * (1.0 + section.at("poisson_ratio").open_interval(-1.0, 0.5)));
  const int edges = section.has("edges_per_bar") ? section.at("edges_per_bar").integer(1) : 16;
  if (edges > 100000) section.at("edges_per_bar").fail("at most 100000");
  if (section.has("pattern")) {
    for (const char* key : {"lattice", "joints", "bars"})
      if (section.has(key)) section.at(key).fail("give either \"pattern\" or the lattice, joints and bars");
    const std::string pattern = section.at("pattern").choice({"square", "honeycomb"});
    const double l = section.at("bar_length").positive();
    scene.network = pattern == "square" ? square_rod_lattice(l, radius, E, G, edges)
                                        : honeycomb_rod_lattice(l, radius, E, G, edges);
  } else {
    if (section.has("bar_length")) section.at("bar_length").fail("applies to a \"pattern\" only");
    RodNetwork& n = scene.network;
    const std::vector<SceneNode> rows = section.at("lattice").items();
    if (rows.size() != 2) section.at("lattice").fail("expected 2 lattice vectors (a planar network)");
    for (int k = 0; k < 2; ++k) n.lattice.col(k) = rows[static_cast<std::size_t>(k)].vector(2);
    if (!(n.lattice.determinant() > 0.0))
      section.at("lattice").fail("the lattice vectors must be right-handed and independent (det > 0)");
    const std::vector<SceneNode> joints = section.at("joints").items();
    if (joints.empty()) section.at("joints").fail("need at least one joint");
    n.joints.resize(static_cast<Eigen::Index>(joints.size()), 2);
    for (std::size_t j = 0; j < joints.size(); ++j)
      n.joints.row(static_cast<Eigen::Index>(j)) = joints[j].vector(2).transpose();
    for (const SceneNode& bar : section.at("bars").items()) {
      bar.expect_keys({"from", "to", "shift"});
      RodNetworkBar b;
      b.from = bar.at("from").integer(0);
      b.to = bar.at("to").integer(0);
      for (const char* key : {"from", "to"})
        if (bar.at(key).integer(0) >= n.joints.rows())
          bar.at(key).fail("no such joint (there are " + std::to_string(n.joints.rows()) + ")");
      if (bar.has("shift")) {
        const std::vector<int> shift = bar.at("shift").integers(INT_MIN);
        if (shift.size() != 2) bar.at("shift").fail("expected 2 integers (multiples of a_1 and a_2)");
        b.shift = Eigen::Vector2i(shift[0], shift[1]);
      }
      n.bars.push_back(b);
    }
    n.youngs_modulus = E;
    n.shear_modulus = G;
    n.radius = radius;
    n.edges_per_bar = edges;
  }
  if (section.has("depth")) scene.depth = section.at("depth").positive();
  try {
    scene.network.validate();
  } catch (const std::invalid_argument& e) {
    section.fail(e.what());
  }
  return scene;
}

}  // namespace tailor
