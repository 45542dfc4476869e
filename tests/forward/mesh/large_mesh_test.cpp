// A 200k-tetrahedron box through every reader, the VTU writer and the facet queries:
// results must match the generated mesh exactly (the times are printed, not asserted: timings belong in bench/).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "forward/mesh/generate.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

namespace tailor::large_mesh_test {
namespace {

using test::ScratchDir;

template <class Work>
double seconds(Work work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void write_gmsh22(const std::string& path, const Mesh& mesh) {
  std::ofstream out(path);
  out.precision(17);
  out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << mesh.num_vertices() << "\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    out << v + 1 << " " << mesh.rest_positions(v, 0) << " " << mesh.rest_positions(v, 1) << " "
        << mesh.rest_positions(v, 2) << "\n";
  }
  out << "$EndNodes\n$Elements\n" << mesh.num_elements() << "\n";
  for (int e = 0; e < mesh.num_elements(); ++e) {
    out << e + 1 << " 4 2 " << e % 3 << " 1";
    for (int k = 0; k < 4; ++k) out << " " << mesh.elements(e, k) + 1;
    out << "\n";
  }
  out << "$EndElements\n";
}

void write_medit(const std::string& path, const Mesh& mesh) {
  std::ofstream out(path);
  out.precision(17);
  out << "MeshVersionFormatted 2\nDimension 3\nVertices\n" << mesh.num_vertices() << "\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    out << mesh.rest_positions(v, 0) << " " << mesh.rest_positions(v, 1) << " " << mesh.rest_positions(v, 2)
        << " 0\n";
  }
  out << "Tetrahedra\n" << mesh.num_elements() << "\n";
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int k = 0; k < 4; ++k) out << mesh.elements(e, k) + 1 << " ";
    out << e % 3 << "\n";
  }
  out << "End\n";
}

TEST(LargeMesh, ReadersWriterAndFacetQueriesScale) {
  ScratchDir dir;
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 1.1, 1.3), 32, 32, 33);
  ASSERT_EQ(mesh.num_elements(), 202752);
  for (int e = 0; e < mesh.num_elements(); ++e) mesh.element_regions[e] = e % 3;

  const std::string msh = dir.path("big.msh"), medit = dir.path("big.mesh"), vtu = dir.path("big.vtu");
  write_gmsh22(msh, mesh);
  write_medit(medit, mesh);

  Mesh from_msh, from_medit;
  const double t_msh = seconds([&] { from_msh = read_gmsh(msh); });
  const double t_medit = seconds([&] { from_medit = read_medit(medit); });
  for (const Mesh* read : {&from_msh, &from_medit}) {
    EXPECT_EQ(read->rest_positions, mesh.rest_positions);  // 17 digits: exact
    EXPECT_EQ(read->elements, mesh.elements);
    EXPECT_EQ(read->element_regions, mesh.element_regions);
  }
  VtkFields fields;
  fields.point["displacement"] = mesh.rest_positions;
  const double t_vtu = seconds([&] { write_vtu(vtu, mesh, fields); });

  Eigen::MatrixXi boundary, adjacency;
  const double t_facets = seconds([&] {
    boundary = boundary_facets(mesh);
    adjacency = element_adjacency(mesh);
  });
  EXPECT_EQ(boundary.rows(), 4 * (32 * 32 + 32 * 33 + 33 * 32));
  EXPECT_EQ(4 * mesh.num_elements(), boundary.rows() + 2 * adjacency.rows());

  std::printf(
      "202752 tets: read .msh %.2f s, read .mesh %.2f s, write .vtu %.2f s, facets+adjacency %.2f s\n", t_msh,
      t_medit, t_vtu, t_facets);
}

}  // namespace
}  // namespace tailor::large_mesh_test
