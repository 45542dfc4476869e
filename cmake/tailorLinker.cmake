# Linker (docs/testing.md, "Build time"). GCC builds link with gold, which binutils installs next
# to the default linker and which links a test program in about half the time (problems_tests:
# 1.7 s -> 0.8 s). TAILOR_LINKER=default keeps the compiler's own choice; the sanitizer build
# (clang) always does.
include_guard(GLOBAL)
set(TAILOR_LINKER gold CACHE STRING "Linker for GCC builds: gold (when it works) or default")
set_property(CACHE TAILOR_LINKER PROPERTY STRINGS gold default)
if(TAILOR_LINKER STREQUAL "gold" AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  include(CheckLinkerFlag)
  check_linker_flag(CXX "-fuse-ld=gold" TAILOR_HAVE_GOLD)
  if(TAILOR_HAVE_GOLD)
    add_link_options(-fuse-ld=gold)
  endif()
endif()
