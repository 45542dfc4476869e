#include "problems/output_process.hpp"

namespace tailor {
namespace {

bool& output_flag() {
  static bool writes = true;
  return writes;
}

}  // namespace

void set_writes_output(bool writes) { output_flag() = writes; }
bool writes_output() { return output_flag(); }

}  // namespace tailor
