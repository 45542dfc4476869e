// Gmsh .msh files (ASCII 2.2 and 4.1) through read_gmsh, as `tailor` reads a scene's mesh.
#include "forward/mesh/mesh_io.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = tailor::fuzz::write_input("input.msh", tailor::fuzz::as_text(data, size));
  tailor::fuzz::expect_clean([&] { tailor::read_mesh(path); });
  return 0;
}
