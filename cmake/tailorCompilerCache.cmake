# Compiler cache (docs/testing.md, "Build time"). With Debian's ccache installed
# (scripts/install-deps.sh installs it), every compile goes through it, with the cache's base
# directory set to the checkout's parent folder: ccache then rewrites the absolute paths inside
# it as relative ones, so that a fresh clone in another folder (CI's) reuses the cache of earlier
# builds on the same machine. CCACHE_NOHASHDIR keeps the build folder out of the key of builds
# with debug information (the sanitizer build's line tables). An explicit
# CMAKE_CXX_COMPILER_LAUNCHER, or TAILOR_CCACHE=OFF, turns this off.
include_guard(GLOBAL)
set(TAILOR_CCACHE AUTO CACHE STRING "Compile through ccache: AUTO (when installed) or OFF")
set_property(CACHE TAILOR_CCACHE PROPERTY STRINGS AUTO OFF)
if(NOT TAILOR_CCACHE STREQUAL "OFF" AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  find_program(TAILOR_CCACHE_PROGRAM ccache)
  if(TAILOR_CCACHE_PROGRAM)
    get_filename_component(_tailor_checkout_parent ${PROJECT_SOURCE_DIR} DIRECTORY)
    set(_tailor_launcher ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${_tailor_checkout_parent} CCACHE_NOHASHDIR=1
        ${TAILOR_CCACHE_PROGRAM})
    set(CMAKE_CXX_COMPILER_LAUNCHER ${_tailor_launcher})
    set(CMAKE_C_COMPILER_LAUNCHER ${_tailor_launcher})
    message(STATUS "Compiler cache: ${TAILOR_CCACHE_PROGRAM} (base directory ${_tailor_checkout_parent})")
  else()
    message(STATUS "Compiler cache: none (Debian: apt-get install ccache)")
  endif()
endif()
