// read_mesh dispatch, and agreement of all readers on the same unit cube and rectangle.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

namespace tailor::read_mesh_test {
namespace {

using test::expect_mesh_error;
using test::mesh_data;
using test::read_text;
using test::ScratchDir;

// Each element as (region, centroid, volume), sorted: independent of vertex and element order.
std::vector<std::array<double, 5>> element_signature(const Mesh& mesh) {
  const Eigen::VectorXd volumes = element_volumes(mesh);
  std::vector<std::array<double, 5>> signature;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    std::array<double, 5> s{double(mesh.element_regions[e]), 0, 0, 0, volumes[e]};
    for (int k = 0; k <= mesh.dim(); ++k) {
      for (int d = 0; d < mesh.dim(); ++d)
        s[1 + d] += mesh.rest_positions(mesh.elements(e, k), d) / (mesh.dim() + 1);
    }
    signature.push_back(s);
  }
  std::sort(signature.begin(), signature.end());
  return signature;
}

void expect_same_elements(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.dim(), b.dim());
  ASSERT_EQ(a.num_elements(), b.num_elements());
  const auto sa = element_signature(a), sb = element_signature(b);
  for (std::size_t i = 0; i < sa.size(); ++i) {
    for (int k = 0; k < 5; ++k) EXPECT_NEAR(sa[i][k], sb[i][k], 1e-14) << "element " << i;
  }
}

TEST(ReadMesh, AllUnitCubeFilesDescribeTheSameMesh) {
  const Mesh reference = read_mesh(mesh_data("unit_cube_v2.msh"));
  EXPECT_NEAR(element_volumes(reference).sum(), 1.0, 1e-14);
  for (const char* name :
       {"unit_cube_v41.msh", "unit_cube.mesh", "unit_cube.node", "unit_cube.ele", "unit_cube"}) {
    SCOPED_TRACE(name);
    expect_same_elements(reference, read_mesh(mesh_data(name)));
  }
}

TEST(ReadMesh, AllRectangleFilesDescribeTheSameMesh) {
  const Mesh reference = read_mesh(mesh_data("rectangle_v2.msh"));
  EXPECT_NEAR(element_volumes(reference).sum(), 2.0, 1e-14);
  expect_same_elements(reference, read_mesh(mesh_data("rectangle.ele")));
  // The 4.1 file has no physical groups: same geometry, region 0.
  const Mesh v41 = read_mesh(mesh_data("rectangle_v41.msh"));
  EXPECT_TRUE((v41.element_regions.array() == 0).all());
  EXPECT_TRUE(v41.rest_positions.isApprox(reference.rest_positions));
  EXPECT_EQ(v41.elements, reference.elements);
}

TEST(ReadMesh, DispatchIsCaseInsensitiveAndRejectsUnknownExtensions) {
  ScratchDir dir;
  const std::string upper = dir.write("CUBE.MSH", read_text(mesh_data("unit_cube_v2.msh")));
  EXPECT_EQ(read_mesh(upper).num_elements(), 12);
  // A TetGen base name with a dot of its own, as TetGen writes them (cube.1.node).
  dir.write("cube.1.node", read_text(mesh_data("unit_cube.node")));
  dir.write("cube.1.ele", read_text(mesh_data("unit_cube.ele")));
  EXPECT_EQ(read_mesh(dir.path("cube.1")).num_elements(), 12);
  const std::string stl = dir.write("cube.stl", "solid cube\n");
  expect_mesh_error([&] { read_mesh(stl); }, {stl, "unknown mesh file extension '.stl'"});
  expect_mesh_error([] { read_mesh("/nonexistent/cube.mesh"); }, {"/nonexistent/cube.mesh", "cannot open"});
  std::filesystem::create_directories(dir.path("folder.msh"));
  expect_mesh_error([&] { read_mesh(dir.path("folder.msh")); }, {dir.path("folder.msh"), "is a directory"});
}

}  // namespace
}  // namespace tailor::read_mesh_test
