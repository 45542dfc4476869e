// Medit reader: the unit cube, a 2D file, keyword layouts, and malformed input.
#include <gtest/gtest.h>

#include <string>

#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

namespace tailor::read_medit_test {
namespace {

using test::expect_mesh_error;
using test::line_of;
using test::mesh_data;
using test::read_text;
using test::replaced;
using test::ScratchDir;

TEST(ReadMedit, UnitCubeWithReferencesAsRegions) {
  const Mesh mesh = read_medit(mesh_data("unit_cube.mesh"));
  ASSERT_EQ(mesh.dim(), 3);
  EXPECT_EQ(mesh.num_vertices(), 9);
  ASSERT_EQ(mesh.num_elements(), 12);  // the boundary Triangles are not elements of a tet mesh
  EXPECT_NEAR(element_volumes(mesh).sum(), 1.0, 1e-14);
  EXPECT_EQ((mesh.element_regions.array() == 1).count(), 6);
  EXPECT_EQ((mesh.element_regions.array() == 2).count(), 6);
  EXPECT_EQ(mesh.elements.row(0), Eigen::RowVector4i(0, 6, 4, 8));  // 1-based in the file
}

TEST(ReadMedit, KeywordValuesOnTheSameLineAndTwoDimensionalFiles) {
  ScratchDir dir;
  const std::string path = dir.write("square.mesh",
                                     "MeshVersionFormatted 2 # comment after a value\n"
                                     "Dimension 2\n"
                                     "Vertices 4\n"
                                     "0 0 3\n1 0 3\n1 1 3\n0 1 3\n"
                                     "Edges\n1\n1 2 9\n"
                                     "Triangles 2\n"
                                     "1 2 3 4\n"
                                     "1 3 4 5\n"
                                     "End\n"
                                     "anything after End is ignored\n");
  const Mesh mesh = read_medit(path);
  ASSERT_EQ(mesh.dim(), 2);
  ASSERT_EQ(mesh.num_elements(), 2);
  EXPECT_NEAR(element_volumes(mesh).sum(), 1.0, 1e-15);
  EXPECT_EQ(mesh.element_regions, Eigen::Vector2i(4, 5));

  // A 3D file with only (planar) triangles is a 2D mesh as well.
  const std::string flat = dir.write("flat.mesh",
                                     "Dimension 3\nVertices 3\n0 0 1 0\n1 0 1 0\n0 1 1 0\n"
                                     "Triangles 1\n1 2 3 0\nEnd\n");
  EXPECT_EQ(read_medit(flat).dim(), 2);
}

TEST(ReadMedit, MissingFile) {
  expect_mesh_error([] { read_medit("/nonexistent/cube.mesh"); }, {"/nonexistent/cube.mesh", "cannot open"});
}

TEST(ReadMedit, VertexNumberOutOfRangeNamesLineAndElement) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube.mesh"));
  const int line = line_of(text, "5 7 8 9 2");
  const std::string too_big = dir.write("big.mesh", replaced(text, "5 7 8 9 2", "5 7 99 9 2"));
  expect_mesh_error([&] { read_medit(too_big); }, {too_big + ":" + std::to_string(line) + ":",
                                                   "element 12 references vertex 99", "only 9 vertices"});
  const std::string zero = dir.write("zero.mesh", replaced(text, "5 7 8 9 2", "5 7 0 9 2"));
  expect_mesh_error([&] { read_medit(zero); },
                    {zero + ":" + std::to_string(line) + ":", "vertex 0", "numbered from 1"});
}

TEST(ReadMedit, MalformedAndTruncatedInput) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube.mesh"));
  const int vertex_line = line_of(text, "0.5 0.5 0.5 0");
  const std::string nan = dir.write("nan.mesh", replaced(text, "0.5 0.5 0.5 0", "0.5 -nan 0.5 0"));
  expect_mesh_error([&] { read_medit(nan); },
                    {nan + ":" + std::to_string(vertex_line) + ":", "not a finite"});
  const std::string no_ref = dir.write("no_ref.mesh", replaced(text, "0.5 0.5 0.5 0", "0.5 0.5 0.5"));
  expect_mesh_error([&] { read_medit(no_ref); },
                    {no_ref + ":" + std::to_string(vertex_line) + ":", "vertex reference"});
  const int tet_line = line_of(text, "3 8 7 9 2");
  const std::string bad_ref = dir.write("bad_ref.mesh", replaced(text, "3 8 7 9 2", "3 8 7 9 x2"));
  expect_mesh_error([&] { read_medit(bad_ref); }, {bad_ref + ":" + std::to_string(tet_line) + ":", "'x2'"});

  const std::string truncated = dir.write("truncated.mesh", text.substr(0, text.find("3 4 8 9 2")));
  expect_mesh_error([&] { read_medit(truncated); },
                    {truncated + ":", "unexpected end of file", "Tetrahedra 8 of 12"});
  const std::string no_count = dir.write("no_count.mesh", text.substr(0, text.find("12\n1 7 5 9 1")));
  expect_mesh_error([&] { read_medit(no_count); },
                    {no_count + ":", "unexpected end of file", "number of Tetrahedra"});
}

TEST(ReadMedit, StructuralErrors) {
  ScratchDir dir;
  const std::string late_dim = dir.write("late.mesh", "Vertices\n1\n0 0 0 0\nDimension 3\nEnd\n");
  expect_mesh_error([&] { read_medit(late_dim); }, {late_dim + ":1:", "before Dimension"});
  const std::string bad_dim = dir.write("dim4.mesh", "# header\nDimension\n4\n");
  expect_mesh_error([&] { read_medit(bad_dim); }, {bad_dim + ":3:", "Dimension is 4"});
  const std::string unknown = dir.write("unknown.mesh", "Dimension 3\nFancyKeyword here\n");
  expect_mesh_error([&] { read_medit(unknown); }, {unknown + ":2:", "FancyKeyword", "record count"});
  const std::string empty = dir.write("empty.mesh", "Dimension 3\nVertices 0\nEnd\n");
  expect_mesh_error([&] { read_medit(empty); }, {empty, "no Tetrahedra or Triangles"});
}

TEST(ReadMedit, InvertedTetrahedronIsRejectedNotFlipped) {
  ScratchDir dir;
  const std::string text = read_text(mesh_data("unit_cube.mesh"));
  const int line = line_of(text, "1 3 7 9 1");
  const std::string inverted = dir.write("inverted.mesh", replaced(text, "1 3 7 9 1", "1 7 3 9 1"));
  expect_mesh_error([&] { read_medit(inverted); },
                    {inverted + ":" + std::to_string(line) + ":", "element 1 (0-based) is inverted", "swap"});
}

}  // namespace
}  // namespace tailor::read_medit_test
