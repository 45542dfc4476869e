// One program for every bench: bin/tailor_bench. Each bench (bench/<name>_bench.cpp) keeps its
// own name as a link to this program, bin/<name>_bench, and runs when called by that name; or
// call `tailor_bench <name>_bench [flags]`. The list of benches is generated from the files in
// bench/ at configure time (bench/CMakeLists.txt), so a new bench is one new file.
#include <cstdio>
#include <cstring>
#include <string>

#include "forward/solve/blas_info.hpp"

// TAILOR_BENCH(name) for each bench, in bench_programs.inc.
#define TAILOR_BENCH(name)        \
  namespace tailor::bench::name { \
  int run(int argc, char** argv); \
  }
#include "bench_programs.inc"
#undef TAILOR_BENCH

namespace {

struct Program {
  const char* name;
  int (*run)(int, char**);
};

#define TAILOR_BENCH(name) {#name, &tailor::bench::name::run},
constexpr Program kPrograms[] = {
#include "bench_programs.inc"
};
#undef TAILOR_BENCH

const Program* find(const char* name) {
  for (const Program& p : kPrograms)
    if (std::strcmp(p.name, name) == 0) return &p;
  return nullptr;
}

std::string base_name(const char* path) {
  const char* slash = std::strrchr(path, '/');
  return slash ? slash + 1 : path;
}

}  // namespace

int main(int argc, char** argv) {
  tailor::use_cpu_blas_core(argv);  // as bin/tailor does: OpenBLAS's kernels for this CPU
  if (argc >= 1) {
    if (const Program* p = find(base_name(argv[0]).c_str())) return p->run(argc, argv);
  }
  if (argc >= 2) {
    if (const Program* p = find(argv[1])) return p->run(argc - 1, argv + 1);
  }
  std::fprintf(stderr, "usage: tailor_bench BENCH [flags]   (or run bin/BENCH)\nbenches:\n");
  for (const Program& p : kPrograms) std::fprintf(stderr, "  %s\n", p.name);
  return (argc >= 2) ? 2 : 0;
}
