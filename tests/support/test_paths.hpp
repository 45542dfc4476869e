#pragma once
// Where the tests find the source tree, its test data and the build tree. Run-time strings
// (tests/support/test_paths.cpp.in, configured per build folder) rather than compile-time
// definitions: a path in every test's compile flags would tie its compiler-cache entry to the
// checkout's folder, and a fresh clone elsewhere would recompile every test.
namespace tailor::testing {

const char* source_dir();     // the repository root
const char* test_data_dir();  // tests/data in the source tree
const char* binary_dir();     // the build folder (bin/tailor, ...)

}  // namespace tailor::testing
