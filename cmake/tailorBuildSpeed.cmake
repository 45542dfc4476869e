# Toolchain settings that shorten a build without changing what it produces (docs/testing.md,
# "Build time"). Both apply to GCC only; the sanitizer build (clang) keeps its defaults.
#
# - Linker: gold, which binutils installs next to the default linker, links a test program in
#   about half the time (problems_tests: 1.7 s -> 0.8 s). TAILOR_LINKER=default keeps the
#   compiler's own choice.
# - Compiler memory: GCC collects its garbage whenever its heap has grown by a fraction of its
#   size; our batches (one translation unit for 8 files, 1-2 GB of compiler memory each) spend
#   about a tenth of their time in those collections. With TAILOR_COMPILER_HEAP_MB (default
#   4096) as the first collection's threshold, a batch finishes before it is reached: a
#   forward batch 60 s -> 44 s, at 2.0 GB instead of 1.7 GB. 0 keeps GCC's own thresholds.
include_guard(GLOBAL)
set(TAILOR_LINKER gold CACHE STRING "Linker for GCC builds: gold (when it works) or default")
set_property(CACHE TAILOR_LINKER PROPERTY STRINGS gold default)
set(TAILOR_COMPILER_HEAP_MB 4096 CACHE STRING
    "GCC: heap size (MB) before its first garbage collection; 0 keeps GCC's default")
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  if(TAILOR_LINKER STREQUAL "gold")
    include(CheckLinkerFlag)
    check_linker_flag(CXX "-fuse-ld=gold" TAILOR_HAVE_GOLD)
    if(TAILOR_HAVE_GOLD)
      add_link_options(-fuse-ld=gold)
    endif()
  endif()
  if(NOT TAILOR_COMPILER_HEAP_MB MATCHES "^[0-9]+$")
    message(FATAL_ERROR "TAILOR_COMPILER_HEAP_MB must be a whole number of MB, not '${TAILOR_COMPILER_HEAP_MB}'")
  endif()
  if(TAILOR_COMPILER_HEAP_MB GREATER 0)
    math(EXPR _tailor_heap_kb "${TAILOR_COMPILER_HEAP_MB} * 1024")
    add_compile_options("SHELL:--param ggc-min-heapsize=${_tailor_heap_kb}" "SHELL:--param ggc-min-expand=100")
  endif()
endif()
