// Record counts in file headers are promises the file may not keep: a header announcing 10^8
// records in a file of a few bytes is refused at the end of the file, without reserving memory
// for the records first. (Found by fuzz/medit_fuzzer.cpp and fuzz/tetgen_fuzzer.cpp: such
// files made the readers reserve 3-6 GB, a std::bad_alloc on smaller machines.) Also: numbers
// in headers that do not fit an int are refused, not truncated into a valid value.
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>
#include <string>

#include "forward/mesh/mesh_io.hpp"
#include "mesh_test_support.hpp"

// The largest single request to the global operator new since the last reset, to see what a
// reader reserves (std::vector's storage comes from here).
namespace {
std::size_t g_largest_request = 0;
}

void* operator new(std::size_t size) {
  g_largest_request = std::max(g_largest_request, size);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace tailor::record_count_test {
namespace {

using test::expect_mesh_error;
using test::ScratchDir;

constexpr std::size_t kMiB = 1024 * 1024;

// Reads `path` expecting a MeshError with all `parts`, and at most 1 MiB per allocation.
void expect_refused_without_reserving(const std::string& path, std::initializer_list<std::string> parts) {
  g_largest_request = 0;
  expect_mesh_error([&] { read_mesh(path); }, parts);
  EXPECT_LT(g_largest_request, kMiB) << path << ": the reader asked for " << g_largest_request << " bytes";
}

TEST(RecordCounts, MeditCountsBeyondTheFileReserveNothing) {
  ScratchDir dir;
  // 268435455 = INT_MAX / 8, the largest count the reader accepts.
  expect_refused_without_reserving(
      dir.write("vertices.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n268435455\n0 0 0 0\n"),
      {"vertices.mesh", "unexpected end of file while reading Vertices 2 of 268435455"});
  expect_refused_without_reserving(
      dir.write(
          "tets.mesh",
          "Dimension 3\nVertices 4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra 268435455\n1 2 3 4 0\n"),
      {"tets.mesh", "unexpected end of file while reading Tetrahedra 2 of 268435455"});
}

TEST(RecordCounts, TetgenCountsBeyondTheFileReserveNothing) {
  ScratchDir dir;
  const std::string points = "0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  dir.write("points.node", "268435455 3 0 0\n" + points);
  dir.write("points.ele", "1 4 0\n0 0 1 2 3\n");
  expect_refused_without_reserving(
      dir.path("points.node"), {"points.node", "unexpected end of file while reading point 5 of 268435455"});
  dir.write("elements.node", "4 3 0 0\n" + points);
  dir.write("elements.ele", "268435455 4 5\n0 0 1 2 3 1 1 1 1 1\n");
  expect_refused_without_reserving(
      dir.path("elements.ele"),
      {"elements.ele", "unexpected end of file while reading element 2 of 268435455"});
}

TEST(RecordCounts, HeaderNumbersBeyondIntAreRefusedNotTruncated) {
  ScratchDir dir;
  // 2^32 + 3 would become 3 in an int.
  expect_mesh_error([&] { read_mesh(dir.write("dim.mesh", "Dimension 4294967299\n")); },
                    {"dim.mesh:1", "Dimension is 4294967299, expected 2 or 3"});
  const std::string points = "0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  dir.write("nodes.node", "4 3 0 0\n" + points);
  dir.write("nodes.ele", "1 4294967300 0\n0 0 1 2 3\n");  // 2^32 + 4
  expect_mesh_error([&] { read_mesh(dir.path("nodes.ele")); },
                    {"nodes.ele:1", "nodes per element is 4294967300"});
  // Gmsh element type 2^32 + 4 (not a tetrahedron, type 4).
  const std::string gmsh =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
      "$Elements\n1\n1 4294967300 0 1 2 3 4\n$EndElements\n";
  expect_mesh_error([&] { read_mesh(dir.write("type.msh", gmsh)); },
                    {"type.msh:13", "element type is 4294967300"});
}

}  // namespace
}  // namespace tailor::record_count_test
