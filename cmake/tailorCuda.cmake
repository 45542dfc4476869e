# The optional CUDA path of the descent solver (docs/dynamics.md, "The GPU path"). AUTO: built
# when CMake finds a CUDA compiler (check_language); ON: required; OFF: not looked for. Without
# one, nothing here is compiled and the descent solver runs on the CPU.
set(TAILOR_WITH_CUDA AUTO CACHE STRING "CUDA path of the descent solver: AUTO, ON or OFF")
set_property(CACHE TAILOR_WITH_CUDA PROPERTY STRINGS AUTO ON OFF)
set(TAILOR_HAVE_CUDA OFF)
if(NOT TAILOR_WITH_CUDA STREQUAL "OFF")
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    # Data-centre GPUs (A100: 80, H100/H200: 90) unless the configure names others
    # (-DCMAKE_CUDA_ARCHITECTURES=...; "native" needs a GPU at configure time).
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES 80 90)
    endif()
    enable_language(CUDA)
    set(TAILOR_HAVE_CUDA ON)
  elseif(TAILOR_WITH_CUDA STREQUAL "ON")
    message(FATAL_ERROR "TAILOR_WITH_CUDA=ON, but CMake found no CUDA compiler (nvcc)")
  else()
    message(STATUS "CUDA: no compiler found; the descent solver runs on the CPU only")
  endif()
endif()

if(TAILOR_HAVE_CUDA)
  # The device kernels of a descent iteration's vector part (forward/dynamics/descent_cuda.cu).
  add_library(tailor_descent_cuda STATIC ${PROJECT_SOURCE_DIR}/forward/dynamics/descent_cuda.cu)
  target_include_directories(tailor_descent_cuda PUBLIC ${PROJECT_SOURCE_DIR})
  set_target_properties(tailor_descent_cuda PROPERTIES CUDA_STANDARD 17 CUDA_ARCHITECTURES "${CMAKE_CUDA_ARCHITECTURES}"
                                                       POSITION_INDEPENDENT_CODE ON)
  target_compile_definitions(tailor_descent_cuda PUBLIC TAILOR_HAVE_CUDA=1)
  # Host code that calls it (the device test) needs only the header and the CUDA runtime.
  find_package(CUDAToolkit REQUIRED)
  target_link_libraries(tailor_descent_cuda PUBLIC CUDA::cudart)
endif()
