// write_vtu: structure of the XML, exact round trip of the numbers, field layouts, errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/mesh/generate.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

namespace tailor::write_vtu_test {
namespace {

using test::read_text;
using test::ScratchDir;

int count_of(const std::string& text, const std::string& needle) {
  int count = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++count;
  return count;
}

// The numbers of the DataArray whose opening tag contains `anchor` (e.g. `Name="u"`), or
// of the first DataArray inside the element `anchor` (e.g. `<Points>`).
std::vector<double> data_array(const std::string& xml, const std::string& anchor) {
  std::size_t tag = xml.find(anchor);
  EXPECT_NE(tag, std::string::npos) << anchor;
  if (tag == std::string::npos) return {};
  if (anchor.front() == '<' && anchor.rfind("<DataArray", 0) != 0) tag = xml.find("<DataArray", tag);
  const std::size_t begin = xml.find('>', tag) + 1;
  const std::size_t end = xml.find("</DataArray>", begin);
  std::istringstream in(xml.substr(begin, end - begin));
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

TEST(WriteVtu, TetMeshWithFieldsRoundTripsExactly) {
  ScratchDir dir;
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0 / 3.0, 0.7, 0.1), 2, 1, 2);
  mesh.element_regions = Eigen::VectorXi::LinSpaced(mesh.num_elements(), 0, mesh.num_elements() - 1);
  const int n = mesh.num_vertices(), m = mesh.num_elements();
  VtkFields fields;
  fields.point["temperature"] = Eigen::VectorXd::LinSpaced(n, 0.1, 1.0 / 7.0);
  fields.point["displacement"] = Eigen::MatrixXd::Random(n, 3);
  fields.cell["stress"] = Eigen::MatrixXd::Random(m, 9);
  const std::string path = dir.path("box.vtu");
  write_vtu(path, mesh, fields);
  const std::string xml = read_text(path);

  EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
  EXPECT_NE(xml.find("type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(xml.find("NumberOfPoints=\"" + std::to_string(n) + "\""), std::string::npos);
  EXPECT_NE(xml.find("NumberOfCells=\"" + std::to_string(m) + "\""), std::string::npos);
  EXPECT_EQ(count_of(xml, "<DataArray"), count_of(xml, "</DataArray>"));
  EXPECT_EQ(count_of(xml, "<DataArray"), 8);  // 2 point, 2 cell fields, points, 3 cell arrays
  EXPECT_EQ(xml.substr(xml.size() - 11), "</VTKFile>\n");

  // Full precision: every number reads back bit for bit.
  const std::vector<double> points = data_array(xml, "<Points>");
  ASSERT_EQ(points.size(), 3u * n);
  for (int v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(points[3 * v + k], mesh.rest_positions(v, k));
  }
  const std::vector<double> temperature = data_array(xml, "Name=\"temperature\"");
  ASSERT_EQ(temperature.size(), std::size_t(n));
  for (int v = 0; v < n; ++v) EXPECT_EQ(temperature[v], fields.point["temperature"](v, 0));
  const std::vector<double> stress = data_array(xml, "Name=\"stress\" NumberOfComponents=\"9\"");
  ASSERT_EQ(stress.size(), 9u * m);
  for (int e = 0; e < m; ++e) {
    for (int k = 0; k < 9; ++k) EXPECT_EQ(stress[9 * e + k], fields.cell["stress"](e, k));
  }
  EXPECT_EQ(data_array(xml, "Name=\"displacement\" NumberOfComponents=\"3\"").size(), 3u * n);

  const std::vector<double> connectivity = data_array(xml, "Name=\"connectivity\"");
  ASSERT_EQ(connectivity.size(), 4u * m);
  for (int e = 0; e < m; ++e) {
    for (int k = 0; k < 4; ++k) EXPECT_EQ(connectivity[4 * e + k], mesh.elements(e, k));
  }
  const std::vector<double> offsets = data_array(xml, "Name=\"offsets\"");
  ASSERT_EQ(offsets.size(), std::size_t(m));
  EXPECT_EQ(offsets.back(), 4.0 * m);
  const std::vector<double> types = data_array(xml, "Name=\"types\"");
  ASSERT_EQ(types.size(), std::size_t(m));
  for (const double t : types) EXPECT_EQ(t, 10.0);
  const std::vector<double> regions = data_array(xml, "<DataArray type=\"Int32\" Name=\"region\"");
  ASSERT_EQ(regions.size(), std::size_t(m));
  EXPECT_EQ(regions[5], 5.0);
}

TEST(WriteVtu, TwoDimensionalMeshesArePaddedToThree) {
  ScratchDir dir;
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 2, 1);
  const int n = mesh.num_vertices(), m = mesh.num_elements();
  VtkFields fields;
  fields.point["velocity"] = Eigen::MatrixXd::Constant(n, 2, 1.5);
  Eigen::MatrixXd strain(m, 4);
  for (int e = 0; e < m; ++e) strain.row(e) << 1, 2, 3, 4;  // row-major 2x2
  fields.cell["strain"] = strain;
  Eigen::MatrixXd deformed = mesh.rest_positions * 2.0;
  const std::string path = dir.path("rect.vtu");
  write_vtu(path, mesh, fields, &deformed);
  const std::string xml = read_text(path);

  const std::vector<double> points = data_array(xml, "<Points>");
  ASSERT_EQ(points.size(), 3u * n);
  for (int v = 0; v < n; ++v) {
    EXPECT_EQ(points[3 * v], deformed(v, 0));  // the given positions, not the rest shape
    EXPECT_EQ(points[3 * v + 1], deformed(v, 1));
    EXPECT_EQ(points[3 * v + 2], 0.0);
  }
  const std::vector<double> velocity = data_array(xml, "Name=\"velocity\" NumberOfComponents=\"3\"");
  ASSERT_EQ(velocity.size(), 3u * n);
  EXPECT_EQ(velocity[0], 1.5);
  EXPECT_EQ(velocity[2], 0.0);
  const std::vector<double> tensor = data_array(xml, "Name=\"strain\" NumberOfComponents=\"9\"");
  ASSERT_EQ(tensor.size(), 9u * m);
  const std::vector<double> expected = {1, 2, 0, 3, 4, 0, 0, 0, 0};
  for (int k = 0; k < 9; ++k) EXPECT_EQ(tensor[k], expected[k]) << "component " << k;
  for (const double t : data_array(xml, "Name=\"types\"")) EXPECT_EQ(t, 5.0);
}

TEST(WriteVtu, FieldNamesAreEscaped) {
  ScratchDir dir;
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 1, 1);
  VtkFields fields;
  fields.cell["a<b & \"c\""] = Eigen::VectorXd::Ones(2);
  write_vtu(dir.path("escaped.vtu"), mesh, fields);
  EXPECT_NE(read_text(dir.path("escaped.vtu")).find("Name=\"a&lt;b &amp; &quot;c&quot;\""),
            std::string::npos);
}

TEST(WriteVtu, RejectsMismatchedFieldsAndUnwritablePaths) {
  ScratchDir dir;
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 1, 1, 1);
  const auto expect_invalid = [&](const VtkFields& fields, const std::string& part) {
    try {
      write_vtu(dir.path("bad.vtu"), mesh, fields);
      ADD_FAILURE() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
    }
  };
  VtkFields rows;
  rows.point["pressure"] = Eigen::VectorXd::Zero(7);
  expect_invalid(rows, "'pressure' has 7 rows, expected 8");
  VtkFields cols;
  cols.cell["weird"] = Eigen::MatrixXd::Zero(6, 5);
  expect_invalid(cols, "'weird' has 5 columns");
  VtkFields reserved;
  reserved.cell["region"] = Eigen::VectorXd::Zero(6);
  expect_invalid(reserved, "'region' is reserved");
  EXPECT_FALSE(std::filesystem::exists(dir.path("bad.vtu")));  // nothing half-written

  const Eigen::MatrixXd wrong_positions = Eigen::MatrixXd::Zero(8, 2);
  EXPECT_THROW(write_vtu(dir.path("p.vtu"), mesh, {}, &wrong_positions), std::invalid_argument);

  const std::string unwritable = dir.path("no_such_dir/out.vtu");
  test::expect_mesh_error([&] { write_vtu(unwritable, mesh); }, {unwritable, "cannot write", "No such file"});
}

}  // namespace
}  // namespace tailor::write_vtu_test
