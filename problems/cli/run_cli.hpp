#pragma once
// The `tailor` command line as a library function: bin/tailor's main() calls it, and so can a
// program that first registers its own verbs and scene kinds (problems/scene_kinds.hpp):
//
//   int main(int argc, char** argv) {
//     tailor::register_scene_kind({"lattice", "a \"lattice\" section", ..., {{"simulate", ...}}});
//     return tailor::run_cli(argc, argv);
//   }
//
// Exit codes: 0 success; 1 the solve, a derivative check, the gradient check or the
// optimization failed (or an output could not be written); 2 bad input (scene or mesh errors)
// or bad usage (an unknown verb or flag, a bad flag value, a verb the scene's kind does not
// support).
#include <iosfwd>

namespace tailor {

// argv[0] is the program's name. Output and progress go to `out`, usage and error messages
// to `err`.
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);
// The same with std::cout and std::cerr.
int run_cli(int argc, const char* const* argv);

}  // namespace tailor
