# tailor's dependencies, found the idiomatic way for Debian 12 packages. Used by the build
# and, installed beside tailorConfig.cmake, by projects that call find_package(tailor).
include_guard(GLOBAL)
include(CMakeFindDependencyMacro)
find_package(PkgConfig REQUIRED)

# From find_package(tailor), a missing dependency makes tailor "not found" with the reason
# (find_dependency's contract; tailorConfig.cmake stops there). In tailor's own build there is
# no enclosing find_package, so find_dependency would only warn and carry on to confusing
# "target not found" errors: require the dependency instead.
macro(tailor_find_dependency)
  if(CMAKE_FIND_PACKAGE_NAME STREQUAL "tailor")
    find_dependency(${ARGN})
  else()
    find_package(${ARGN} REQUIRED)
  endif()
endmacro()

# BLAS: follow the system alternative (OpenBLAS when libopenblas0-pthread is installed).
# Plain FindBLAS prefers ATLAS on Debian, which makes CHOLMOD 2.5x slower.
set(BLA_VENDOR Generic)
tailor_find_dependency(BLAS)
tailor_find_dependency(LAPACK)
tailor_find_dependency(Threads)
tailor_find_dependency(OpenMP)

tailor_find_dependency(Eigen3 3.4 CONFIG)
tailor_find_dependency(nlohmann_json 3.10 CONFIG)
# Command lines of `tailor` and the benches (header-only; Debian's libcli11-dev).
tailor_find_dependency(CLI11 2.1 CONFIG)
tailor_find_dependency(NLopt CONFIG)
tailor_find_dependency(PNG)  # the plots (problems/plot/png_writer.cpp)

# Ceres: Debian's exported target hard-links ATLAS (libf77blas, libatlas), which would bind
# every dgemm_ in the process -- CHOLMOD's included -- to ATLAS. Drop them; BLAS comes from the
# system alternative above.
tailor_find_dependency(Ceres CONFIG)
if(TARGET Ceres::ceres)
  get_target_property(_tailor_ceres_libs Ceres::ceres INTERFACE_LINK_LIBRARIES)
  list(FILTER _tailor_ceres_libs EXCLUDE REGEX "libf77blas|libatlas")
  set_target_properties(Ceres::ceres PROPERTIES INTERFACE_LINK_LIBRARIES "${_tailor_ceres_libs}")
endif()

# SuiteSparse 5.x ships neither a CMake config nor a .pc file.
find_path(TAILOR_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(TAILOR_CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(TAILOR_SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
if(NOT TARGET tailor_dep_cholmod)
  add_library(tailor_dep_cholmod INTERFACE IMPORTED)
  set_target_properties(tailor_dep_cholmod PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${TAILOR_CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${TAILOR_CHOLMOD_LIBRARY};${TAILOR_SUITESPARSECONFIG_LIBRARY};BLAS::BLAS;LAPACK::LAPACK")
endif()

# METIS 5.1 (graph partitioning of meshes into domains, forward/reduction/domain_partition.cpp):
# Debian's libmetis-dev ships neither a CMake config nor a .pc file.
find_path(TAILOR_METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(TAILOR_METIS_LIBRARY metis REQUIRED)
if(NOT TARGET tailor_dep_metis)
  add_library(tailor_dep_metis INTERFACE IMPORTED)
  set_target_properties(tailor_dep_metis PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${TAILOR_METIS_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${TAILOR_METIS_LIBRARY}")
endif()

# Ipopt 3.11 (MUMPS) and ARPACK-NG 3.8: pkg-config is what Debian ships for both.
pkg_check_modules(IPOPT REQUIRED IMPORTED_TARGET GLOBAL ipopt)
pkg_check_modules(ARPACK REQUIRED IMPORTED_TARGET GLOBAL arpack)
