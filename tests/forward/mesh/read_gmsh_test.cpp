// Gmsh reader: the hand-written unit cube and rectangle in formats 2.2 and 4.1, and every
// kind of malformed input.
#include <gtest/gtest.h>

#include <string>

#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

namespace tailor::read_gmsh_test {
namespace {

using test::expect_mesh_error;
using test::line_of;
using test::mesh_data;
using test::read_text;
using test::replaced;
using test::ScratchDir;

void expect_unit_cube(const Mesh& mesh) {
  ASSERT_EQ(mesh.dim(), 3);
  EXPECT_EQ(mesh.num_vertices(), 9);
  ASSERT_EQ(mesh.num_elements(), 12);  // boundary triangles, lines and points are dropped
  const Eigen::VectorXd volumes = element_volumes(mesh);
  for (int e = 0; e < 12; ++e) EXPECT_NEAR(volumes[e], 1.0 / 12.0, 1e-15);
  EXPECT_NEAR(volumes.sum(), 1.0, 1e-14);
  EXPECT_EQ(boundary_facets(mesh).rows(), 12);
}

TEST(ReadGmsh, UnitCubeFormat22) {
  const Mesh mesh = read_gmsh(mesh_data("unit_cube_v2.msh"));
  expect_unit_cube(mesh);
  // The first tag of each element is its physical group.
  EXPECT_EQ((mesh.element_regions.array() == 1).count(), 6);
  EXPECT_EQ((mesh.element_regions.array() == 2).count(), 6);
  EXPECT_EQ(mesh.element_regions[0], 1);
  EXPECT_EQ(mesh.element_regions[11], 2);
  EXPECT_TRUE(mesh.rest_positions.row(8).isApprox(Eigen::RowVector3d(0.5, 0.5, 0.5)));
}

TEST(ReadGmsh, UnitCubeFormat41WithSparseNodeTagsAndEntities) {
  const Mesh mesh = read_gmsh(mesh_data("unit_cube_v41.msh"));
  expect_unit_cube(mesh);
  // Node tags 95, 10, 20, ... map to vertices 0, 1, 2, ... in file order.
  EXPECT_TRUE(mesh.rest_positions.row(0).isApprox(Eigen::RowVector3d(0.5, 0.5, 0.5)));
  EXPECT_TRUE(mesh.rest_positions.row(8).isApprox(Eigen::RowVector3d(1, 1, 1)));
  EXPECT_TRUE((mesh.elements.col(3).array() == 0).all());  // every tet has the centre last
  // Volume 1 carries physical tags (1, 7): the first counts. Volume 2 carries 2.
  EXPECT_EQ((mesh.element_regions.head(6).array() == 1).count(), 6);
  EXPECT_EQ((mesh.element_regions.tail(6).array() == 2).count(), 6);
}

TEST(ReadGmsh, Format41WithoutEntitiesHasRegionZero) {
  ScratchDir dir;
  std::string text = read_text(mesh_data("unit_cube_v41.msh"));
  text.erase(text.find("$Entities"), text.find("$Nodes") - text.find("$Entities"));
  const Mesh mesh = read_gmsh(dir.write("no_entities.msh", text));
  expect_unit_cube(mesh);
  EXPECT_TRUE((mesh.element_regions.array() == 0).all());
}

TEST(ReadGmsh, TrianglesOnlyBecomeA2DMesh) {
  for (const char* name : {"rectangle_v2.msh", "rectangle_v41.msh"}) {
    SCOPED_TRACE(name);
    const Mesh mesh = read_gmsh(mesh_data(name));
    ASSERT_EQ(mesh.dim(), 2);  // z dropped (0 in one file, 0.5 in the other)
    EXPECT_EQ(mesh.num_vertices(), 5);
    ASSERT_EQ(mesh.num_elements(), 4);
    EXPECT_NEAR(element_volumes(mesh).sum(), 2.0, 1e-14);
    EXPECT_TRUE(mesh.rest_positions.row(4).isApprox(Eigen::RowVector2d(1.0, 0.5)));
  }
  const Mesh v2 = read_gmsh(mesh_data("rectangle_v2.msh"));
  EXPECT_EQ(v2.element_regions, (Eigen::VectorXi(4) << 7, 8, 7, 8).finished());
}

TEST(ReadGmsh, Format22ElementsWithoutTagsHaveRegionZero) {
  ScratchDir dir;
  std::string text = read_text(mesh_data("rectangle_v2.msh"));
  text = replaced(text, "5 2 2 7 1 1 2 5", "5 2 0 1 2 5");
  text = replaced(text, "6 2 2 8 1 2 3 5", "6 2 1 3 2 3 5");  // one tag: physical only
  const Mesh mesh = read_gmsh(dir.write("few_tags.msh", text));
  EXPECT_EQ(mesh.element_regions, (Eigen::VectorXi(4) << 0, 3, 7, 8).finished());
}

TEST(ReadGmsh, MissingFileNamesThePath) {
  expect_mesh_error([] { read_gmsh("/nonexistent/dir/cube.msh"); },
                    {"/nonexistent/dir/cube.msh", "cannot open"});
}

TEST(ReadGmsh, RejectsBinaryAndUnsupportedVersions) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube_v41.msh"));
  const std::string binary = dir.write("binary.msh", replaced(text, "4.1 0 8", "4.1 1 8"));
  expect_mesh_error([&] { read_gmsh(binary); }, {binary + ":2:", "binary"});
  const std::string v40 = dir.write("v40.msh", replaced(text, "4.1 0 8", "4 0 8"));
  expect_mesh_error([&] { read_gmsh(v40); }, {v40 + ":2:", "unsupported Gmsh format version 4"});
  const std::string v3 = dir.write("v3.msh", replaced(text, "4.1 0 8", "3.0 0 8"));
  expect_mesh_error([&] { read_gmsh(v3); }, {v3 + ":2:", "version 3.0"});
  const std::string not_gmsh = dir.write("medit.msh", read_text(mesh_data("unit_cube.mesh")));
  expect_mesh_error([&] { read_gmsh(not_gmsh); }, {not_gmsh + ":1:", "$MeshFormat"});
  const std::string empty = dir.write("empty.msh", "");
  expect_mesh_error([&] { read_gmsh(empty); }, {empty, "$MeshFormat"});
}

TEST(ReadGmsh, MalformedNumbersNameTheLine) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube_v2.msh"));
  const int line = line_of(text, "9 0.5 0.5 0.5");
  const std::string bad = dir.write("bad.msh", replaced(text, "9 0.5 0.5 0.5", "9 0.5 abc 0.5"));
  expect_mesh_error([&] { read_gmsh(bad); }, {bad + ":" + std::to_string(line) + ":", "'abc'"});
  const std::string nan = dir.write("nan.msh", replaced(text, "9 0.5 0.5 0.5", "9 0.5 nan 0.5"));
  expect_mesh_error([&] { read_gmsh(nan); }, {nan + ":" + std::to_string(line) + ":", "not a finite"});
  const std::string inf = dir.write("inf.msh", replaced(text, "9 0.5 0.5 0.5", "9 0.5 1e999 0.5"));
  expect_mesh_error([&] { read_gmsh(inf); }, {inf + ":" + std::to_string(line) + ":", "not a finite"});
  const std::string short_line = dir.write("short.msh", replaced(text, "9 0.5 0.5 0.5", "9 0.5 0.5"));
  expect_mesh_error([&] { read_gmsh(short_line); },
                    {short_line + ":" + std::to_string(line) + ":", "line ends"});
  const std::string extra = dir.write("extra.msh", replaced(text, "9 0.5 0.5 0.5", "9 0.5 0.5 0.5 7"));
  expect_mesh_error([&] { read_gmsh(extra); }, {extra + ":" + std::to_string(line) + ":", "extra text '7'"});
}

TEST(ReadGmsh, TruncatedFileAndWrongCounts) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube_v2.msh"));
  const std::string truncated = dir.write("truncated.msh", text.substr(0, text.find("5 0 0 1")));
  expect_mesh_error([&] { read_gmsh(truncated); }, {truncated + ":", "unexpected end of file", "$Nodes"});
  // Cut in the middle of an element line.
  const std::size_t cut = text.find("16 4 2 2 2 5") + 8;
  const std::string cut_line = dir.write("cut.msh", text.substr(0, cut));
  expect_mesh_error(
      [&] { read_gmsh(cut_line); },
      {cut_line + ":" + std::to_string(line_of(text, "16 4 2 2 2 5")) + ":", "is it truncated?"});
  const std::string no_end = dir.write("no_end.msh", text.substr(0, text.find("$EndElements")));
  expect_mesh_error([&] { read_gmsh(no_end); }, {no_end + ":", "unexpected end of file", "$EndElements"});
  // One node more than announced: the 9th node line is followed by another instead of $EndNodes.
  const std::string too_many = dir.write("too_many.msh", replaced(text, "$Nodes\n9\n", "$Nodes\n8\n"));
  expect_mesh_error(
      [&] { read_gmsh(too_many); },
      {too_many + ":" + std::to_string(line_of(text, "9 0.5 0.5 0.5")) + ":", "expected $EndNodes"});

  const std::string v4 = read_text(mesh_data("unit_cube_v41.msh"));
  const std::string count = dir.write("count.msh", replaced(v4, "2 9 10 95", "2 10 10 95"));
  expect_mesh_error([&] { read_gmsh(count); }, {count + ":", "announces 10 nodes, but its blocks hold 9"});
  const std::string comment =
      dir.write("comment.msh", replaced(v4, "$EndEntities\n", "$EndEntities\n$Comments\nnever closed\n"));
  expect_mesh_error([&] { read_gmsh(comment); }, {comment + ":", "unexpected end of file", "$Comments"});
}

TEST(ReadGmsh, ElementReferencingAnUndefinedNode) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube_v2.msh"));
  const int line = line_of(text, "16 4 2 2 2");
  const std::string bad = dir.write("cube.msh", replaced(text, "16 4 2 2 2 5 7 8 9", "16 4 2 2 2 5 7 99 9"));
  expect_mesh_error([&] { read_gmsh(bad); }, {bad + ":" + std::to_string(line) + ":",
                                              "element 16 references node 99", "only 9 nodes"});

  const std::string v4 = read_text(mesh_data("unit_cube_v41.msh"));
  const std::string bad4 = dir.write("cube4.msh", replaced(v4, "14 50 70 80 95", "14 50 70 80 15"));
  expect_mesh_error(
      [&] { read_gmsh(bad4); },
      {bad4 + ":" + std::to_string(line_of(v4, "14 50 70 80 95")) + ":", "element 14 references node 15"});
  const std::string twice = dir.write("twice.msh", replaced(v4, "\n20\n", "\n10\n"));
  expect_mesh_error([&] { read_gmsh(twice); }, {twice + ":", "node 10 is defined again"});
}

TEST(ReadGmsh, InvertedAndDegenerateElementsNameTheLine) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube_v2.msh"));
  const int line = line_of(text, "16 4 2 2 2");
  const std::string inverted =
      dir.write("inverted.msh", replaced(text, "16 4 2 2 2 5 7 8 9", "16 4 2 2 2 5 8 7 9"));
  expect_mesh_error([&] { read_gmsh(inverted); }, {inverted + ":" + std::to_string(line) + ":",
                                                   "element 11 (0-based) is inverted", "-0.0833333"});
  const std::string degenerate =
      dir.write("flat.msh", replaced(text, "16 4 2 2 2 5 7 8 9", "16 4 2 2 2 5 7 8 8"));
  expect_mesh_error([&] { read_gmsh(degenerate); },
                    {degenerate + ":" + std::to_string(line) + ":", "degenerate"});
}

TEST(ReadGmsh, RejectsFilesWithoutUsableElements) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("rectangle_v2.msh"));
  // Only the four boundary lines remain.
  const std::string lines_only =
      dir.write("lines.msh", replaced(text.substr(0, text.find("5 2 2 7")), "$Elements\n8", "$Elements\n4") +
                                 "$EndElements\n");
  expect_mesh_error([&] { read_gmsh(lines_only); }, {lines_only, "no tetrahedra"});
  // A triangle surface that is not flat cannot be a 2D mesh.
  const std::string curved = dir.write("curved.msh", replaced(text, "5 1 0.5 0", "5 1 0.5 0.25"));
  expect_mesh_error([&] { read_gmsh(curved); }, {curved, "not in one plane"});
  // Second-order elements are refused rather than silently straightened.
  const std::string quadratic =
      dir.write("quadratic.msh", replaced(text, "5 2 2 7 1 1 2 5", "5 9 2 7 1 1 2 5 1 2 3"));
  expect_mesh_error([&] { read_gmsh(quadratic); },
                    {quadratic + ":" + std::to_string(line_of(text, "5 2 2 7 1")) + ":", "higher-order"});
}

}  // namespace
}  // namespace tailor::read_gmsh_test
