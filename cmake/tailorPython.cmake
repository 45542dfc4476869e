# Finds what the Python module needs: a Python 3 interpreter with NumPy, its headers, and
# pybind11's CMake package (Debian: pybind11-dev python3-dev python3-numpy). Sets
# TAILOR_PYTHON_FOUND, and TAILOR_PYTHON_INSTALL_DIR (the package's folder relative to the install
# prefix). Without them it says what is missing and the build goes on without the module.
include_guard(GLOBAL)
set(TAILOR_PYTHON_FOUND OFF)

# With several Pythons on PATH (a version manager's shim before the system's), take the first
# one that imports NumPy, unless Python3_EXECUTABLE says which.
if(NOT DEFINED Python3_EXECUTABLE)
  find_program(_tailor_path_python NAMES python3 NO_CACHE)
  foreach(_candidate ${_tailor_path_python} /usr/bin/python3)
    if(_candidate AND EXISTS ${_candidate})
      execute_process(COMMAND ${_candidate} -c "import numpy" RESULT_VARIABLE _numpy_missing
                      OUTPUT_QUIET ERROR_QUIET)
      if(_numpy_missing EQUAL 0)
        set(Python3_EXECUTABLE ${_candidate})
        break()
      endif()
    endif()
  endforeach()
endif()

find_package(Python3 3.8 COMPONENTS Interpreter Development.Module NumPy QUIET)
if(Python3_FOUND)
  find_package(pybind11 2.6 CONFIG QUIET)
endif()

if(NOT Python3_Interpreter_FOUND)
  set(_missing "a Python 3 interpreter (python3)")
elseif(NOT Python3_Development.Module_FOUND)
  set(_missing "Python's headers for ${Python3_EXECUTABLE} (python3-dev)")
elseif(NOT Python3_NumPy_FOUND)
  set(_missing "NumPy for ${Python3_EXECUTABLE} (python3-numpy; or -DPython3_EXECUTABLE=<a python with numpy>)")
elseif(NOT pybind11_FOUND)
  set(_missing "pybind11's CMake package (pybind11-dev)")
endif()
if(DEFINED _missing)
  message(STATUS "tailor: not building the Python module: ${_missing} not found "
                 "(scripts/install-deps.sh installs it; -DTAILOR_WITH_PYTHON=OFF silences this)")
  return()
endif()

set(TAILOR_PYTHON_FOUND ON)
# The interpreter's own folder for packages under CMAKE_INSTALL_PREFIX when it has one there
# (Debian's python3 with /usr/local: lib/python3.11/dist-packages, on its sys.path), else the
# standard layout (lib/python3.X/site-packages).
execute_process(COMMAND ${Python3_EXECUTABLE} -c [=[
import os, sys, sysconfig
prefix = os.path.normpath(sys.argv[1])
platlib = os.path.normpath(sysconfig.get_path('platlib'))
if platlib.startswith(prefix + os.sep):
    print(os.path.relpath(platlib, prefix))
else:
    print(os.path.relpath(sysconfig.get_path('platlib', 'posix_prefix', vars={'platbase': prefix, 'base': prefix}), prefix))
]=] ${CMAKE_INSTALL_PREFIX} OUTPUT_VARIABLE _site OUTPUT_STRIP_TRAILING_WHITESPACE)
set(TAILOR_PYTHON_INSTALL_DIR "${_site}" CACHE STRING
    "Where `cmake --install` puts the Python package tailor, relative to CMAKE_INSTALL_PREFIX")
message(STATUS "tailor: Python module for ${Python3_EXECUTABLE} (NumPy ${Python3_NumPy_VERSION}, "
               "pybind11 ${pybind11_VERSION}); installs into <prefix>/${TAILOR_PYTHON_INSTALL_DIR}")
