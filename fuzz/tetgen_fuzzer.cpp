// TetGen .node + .ele pairs through read_tetgen. One input holds both files: the .node text,
// a line "%ele", then the .ele text (an input without that line is a .node file with an empty
// .ele file). The seeds in fuzz/corpus/tetgen are joined this way by scripts/fuzz.sh.
#include "forward/mesh/mesh_io.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = tailor::fuzz::as_text(data, size);
  const std::string separator = "\n%ele\n";
  const std::size_t at = text.find(separator);
  const std::string node = at == std::string::npos ? text : text.substr(0, at + 1);
  const std::string ele = at == std::string::npos ? std::string() : text.substr(at + separator.size());
  tailor::fuzz::write_input("input.node", node);
  tailor::fuzz::write_input("input.ele", ele);
  const std::string base = (tailor::fuzz::scratch_folder() / "input").string();
  tailor::fuzz::expect_clean([&] { tailor::read_mesh(base + ".node"); });
  return 0;
}
