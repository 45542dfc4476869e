// TetGen reader: path forms, 0- and 1-based numbering, attributes, malformed input.
#include <gtest/gtest.h>

#include <string>

#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

namespace tailor::read_tetgen_test {
namespace {

using test::expect_mesh_error;
using test::line_of;
using test::mesh_data;
using test::read_text;
using test::replaced;
using test::ScratchDir;

TEST(ReadTetgen, AnyOfTheThreePathFormsReadsTheSameMesh) {
  const Mesh from_base = read_tetgen(mesh_data("unit_cube"));
  const Mesh from_node = read_tetgen(mesh_data("unit_cube.node"));
  const Mesh from_ele = read_tetgen(mesh_data("unit_cube.ele"));
  ASSERT_EQ(from_base.dim(), 3);
  EXPECT_EQ(from_base.num_vertices(), 9);
  ASSERT_EQ(from_base.num_elements(), 12);
  EXPECT_NEAR(element_volumes(from_base).sum(), 1.0, 1e-14);
  EXPECT_EQ(from_base.elements.row(0), Eigen::RowVector4i(0, 6, 4, 8));  // 1-based in the file
  EXPECT_EQ((from_base.element_regions.array() == 1).count(), 6);
  EXPECT_EQ((from_base.element_regions.array() == 2).count(), 6);
  EXPECT_EQ(from_node.elements, from_base.elements);
  EXPECT_EQ(from_ele.rest_positions, from_base.rest_positions);
}

TEST(ReadTetgen, ZeroBasedTwoDimensionalFiles) {
  const Mesh mesh = read_tetgen(mesh_data("rectangle.node"));
  ASSERT_EQ(mesh.dim(), 2);
  ASSERT_EQ(mesh.num_elements(), 4);
  EXPECT_EQ(mesh.elements.row(0), Eigen::RowVector3i(0, 1, 4));
  EXPECT_NEAR(element_volumes(mesh).sum(), 2.0, 1e-15);
  EXPECT_EQ(mesh.element_regions, (Eigen::VectorXi(4) << 7, 8, 7, 8).finished());
}

TEST(ReadTetgen, QuadraticElementsKeepTheirCorners) {
  ScratchDir dir;
  const std::string base = dir.path("quadratic");
  dir.write("quadratic.node", "4 3\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
  // Without attributes the region is 0; the six mid-edge numbers are not used.
  dir.write("quadratic.ele", "1 10 0\n0 0 1 2 3 0 0 0 0 0 0\n");
  const Mesh mesh = read_tetgen(base);
  ASSERT_EQ(mesh.num_elements(), 1);
  EXPECT_EQ(mesh.elements.row(0), Eigen::RowVector4i(0, 1, 2, 3));
  EXPECT_EQ(mesh.element_regions[0], 0);
}

TEST(ReadTetgen, MissingFilesNameThePath) {
  expect_mesh_error([] { read_tetgen("/nonexistent/cube"); }, {"/nonexistent/cube.node", "cannot open"});
  ScratchDir dir;
  dir.write("lonely.node", read_text(mesh_data("unit_cube.node")));
  expect_mesh_error([&] { read_tetgen(dir.path("lonely.node")); }, {dir.path("lonely.ele"), "cannot open"});
}

TEST(ReadTetgen, NumberingErrors) {
  ScratchDir dir;
  const std::string node = read_text(mesh_data("unit_cube.node"));
  const std::string ele = read_text(mesh_data("unit_cube.ele"));
  dir.write("a.node", node);
  const std::string bad_ele = dir.write("a.ele", replaced(ele, "12 5 7 8 9 2", "12 5 7 8 10 2"));
  expect_mesh_error([&] { read_tetgen(dir.path("a")); },
                    {bad_ele + ":" + std::to_string(line_of(ele, "12 5 7 8 9 2")) + ":",
                     "element 12 references vertex 10", "only 9 vertices", "numbered from 1"});

  dir.write("b.ele", ele);
  const std::string gap = dir.write("b.node", replaced(node, "\n5 0 0 1", "\n6 0 0 1"));
  expect_mesh_error(
      [&] { read_tetgen(dir.path("b")); },
      {gap + ":" + std::to_string(line_of(node, "\n5 0 0 1") + 1) + ":", "point number 6", "5 was expected"});
  const std::string start = dir.write("b.node", replaced(node, "\n1 0 0 0", "\n2 0 0 0"));
  expect_mesh_error([&] { read_tetgen(dir.path("b")); }, {start + ":3:", "first point is numbered 2"});
}

TEST(ReadTetgen, MalformedAndTruncatedInput) {
  ScratchDir dir;
  const std::string node = read_text(mesh_data("unit_cube.node"));
  const std::string ele = read_text(mesh_data("unit_cube.ele"));
  dir.write("c.node", node);
  const std::string truncated = dir.write("c.ele", ele.substr(0, ele.find("10 1 2 4 9 2")));
  expect_mesh_error([&] { read_tetgen(dir.path("c")); },
                    {truncated + ":", "unexpected end of file", "element 10 of 12"});
  const std::string fractional = dir.write("c.ele", replaced(ele, "3 2 8 4 9 1", "3 2 8 4 9 1.5"));
  expect_mesh_error([&] { read_tetgen(dir.path("c")); },
                    {fractional + ":" + std::to_string(line_of(ele, "3 2 8 4 9 1")) + ":",
                     "region attribute 1.5 is not an integer"});
  const std::string wrong_nodes = dir.write("c.ele", replaced(ele, "12 4 1", "12 3 1"));
  expect_mesh_error([&] { read_tetgen(dir.path("c")); }, {wrong_nodes + ":1:", "3 nodes per element"});
  const std::string extra = dir.write("c.ele", replaced(ele, "3 2 8 4 9 1", "3 2 8 4 9 1 4"));
  expect_mesh_error([&] { read_tetgen(dir.path("c")); }, {extra + ":", "extra text '4'"});

  dir.write("d.ele", ele);
  const std::string inf = dir.write("d.node", replaced(node, "9 0.5 0.5 0.5", "9 0.5 inf 0.5"));
  expect_mesh_error([&] { read_tetgen(dir.path("d")); },
                    {inf + ":" + std::to_string(line_of(node, "9 0.5")) + ":", "not a finite"});
  const std::string dim = dir.write("d.node", replaced(node, "9 3 1 1", "9 4 1 1"));
  expect_mesh_error([&] { read_tetgen(dir.path("d")); }, {dim + ":2:", "dimension is 4"});
  const std::string marker = dir.write("d.node", replaced(node, "4 1 1 0 0.5 1", "4 1 1 0 0.5"));
  expect_mesh_error([&] { read_tetgen(dir.path("d")); },
                    {marker + ":" + std::to_string(line_of(node, "4 1 1 0")) + ":", "boundary marker"});
}

TEST(ReadTetgen, InvertedElementNamesTheEleLine) {
  ScratchDir dir;
  dir.write("e.node", read_text(mesh_data("unit_cube.node")));
  const std::string ele = read_text(mesh_data("unit_cube.ele"));
  const std::string inverted = dir.write("e.ele", replaced(ele, "7 3 8 7 9 2", "7 3 7 8 9 2"));
  expect_mesh_error([&] { read_tetgen(dir.path("e")); },
                    {inverted + ":" + std::to_string(line_of(ele, "7 3 8 7 9 2")) + ":",
                     "element 6 (0-based) is inverted"});
}

}  // namespace
}  // namespace tailor::read_tetgen_test
