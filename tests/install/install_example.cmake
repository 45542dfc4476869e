# cmake -DBUILD_DIR=... -DEXAMPLES_DIR=... -DWORK_DIR=... -DCONFIG=... -DGENERATOR=...
#       -DCXX_COMPILER=... -DEXPECTED_VERSION=... -P install_example.cmake
cmake_minimum_required(VERSION 3.22)

set(prefix ${WORK_DIR}/prefix)
set(example_build ${WORK_DIR}/examples-build)
# Start clean: a stale prefix could hide a file the install no longer provides.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run)
  message(STATUS "+ ${ARGN}")
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE result OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  message("${out}")
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})

# Only public headers are installed (tailor_library's PRIVATE_HEADERS are left out): every
# tailor header an installed header includes must be installed too.
set(include_root ${prefix}/include/tailor)
file(GLOB_RECURSE installed_headers RELATIVE ${include_root} ${include_root}/*.hpp)
foreach(header ${installed_headers})
  file(STRINGS ${include_root}/${header} includes REGEX "^#include \"")
  foreach(line ${includes})
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" included "${line}")
    if(NOT EXISTS ${include_root}/${included})
      message(FATAL_ERROR "installed header ${header} includes ${included}, which is not installed")
    endif()
  endforeach()
endforeach()
foreach(private forward/mesh/text_scanner_detail.hpp optimizers/backend_detail.hpp problems/fem/scene_parsing.hpp)
  if(EXISTS ${include_root}/${private})
    message(FATAL_ERROR "the private header ${private} was installed")
  endif()
endforeach()
# CMAKE_FIND_USE_PACKAGE_REGISTRY=OFF: only the scratch prefix may provide tailor.
run(${CMAKE_COMMAND} -S ${EXAMPLES_DIR} -B ${example_build} -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)

file(STRINGS ${example_build}/CMakeCache.txt tailor_dir REGEX "^tailor_DIR:")
if(NOT tailor_dir STREQUAL "tailor_DIR:PATH=${prefix}/lib/cmake/tailor")
  message(FATAL_ERROR "examples/ found tailor outside the install prefix: ${tailor_dir}")
endif()

run(${CMAKE_COMMAND} --build ${example_build} --config ${CONFIG})
run(${example_build}/minimal)
string(FIND "${last_output}" "tailor ${EXPECTED_VERSION}" found)
if(found EQUAL -1)
  message(FATAL_ERROR "minimal did not report tailor ${EXPECTED_VERSION}")
endif()

# Whole problems through the installed API (problems/fem/study.hpp); each exits non-zero unless its
# checks pass (Taylor test, derivative checks) and it reaches what it states (inverse_bar: both
# moduli to 1e-6; custom_objective: the target deflection to 1e-6; custom_energy: the modulus to
# 1e-6; constrained_design: the budget kept and the compliance lowered by 10% or more).
foreach(example inverse_bar custom_objective custom_energy constrained_design)
  run(${example_build}/${example})
  if(NOT EXISTS ${WORK_DIR}/out/${example}/report.json OR NOT EXISTS ${WORK_DIR}/out/${example}/result.vtu)
    message(FATAL_ERROR "${example} did not write out/${example}/report.json and result.vtu")
  endif()
endforeach()
