# python.install: `cmake --install --component python` into a scratch prefix outside the build
# and source trees, then the package imports from PREFIX/PACKAGE_DIR (not from the build tree:
# it runs in PREFIX, as python -c puts the current folder first on sys.path) and solves SCENE.
# The install must not write into BUILD_DIR or SOURCE_DIR: both are listed (tree_snapshot.py)
# before and after, and any file added, removed or changed there fails the test, except the
# install manifest that CMake itself writes into the top of the build folder
# (install_manifest_python.txt, the list of installed files; CMake writes it unconditionally).
set(SNAPSHOT ${CMAKE_CURRENT_LIST_DIR}/tree_snapshot.py)
execute_process(COMMAND ${PYTHON} -c "import tempfile; print(tempfile.mkdtemp(prefix='tailor-install-'))"
                OUTPUT_VARIABLE SCRATCH OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE result)
if(NOT result EQUAL 0 OR NOT IS_DIRECTORY "${SCRATCH}")
  message(FATAL_ERROR "cannot make a scratch folder")
endif()
set(PREFIX ${SCRATCH}/prefix)

function(check_install)
  execute_process(COMMAND ${PYTHON} ${SNAPSHOT} take ${SCRATCH}/before.json ${BUILD_DIR} ${SOURCE_DIR}
                  RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    set(failure "cannot list the build and source trees" PARENT_SCOPE)
    return()
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --component python
                  RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    set(failure "cmake --install --component python failed" PARENT_SCOPE)
    return()
  endif()
  execute_process(COMMAND ${PYTHON} ${SNAPSHOT} take ${SCRATCH}/after.json ${BUILD_DIR} ${SOURCE_DIR})
  execute_process(COMMAND ${PYTHON} ${SNAPSHOT} compare ${SCRATCH}/before.json ${SCRATCH}/after.json
                          --allow ${BUILD_DIR}/install_manifest_python.txt
                  RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    set(failure "cmake --install wrote into the build or source tree (listed above)" PARENT_SCOPE)
    return()
  endif()

  set(ENV{PYTHONPATH} ${PREFIX}/${PACKAGE_DIR})
  set(ENV{PYTHONDONTWRITEBYTECODE} 1)
  execute_process(COMMAND ${PYTHON} -c "
import sys, tailor
assert tailor.__file__.startswith(sys.argv[1]), tailor.__file__
report = tailor.simulate(sys.argv[2])
assert report.ok and report['fields']['displacement'].shape[0] == report['mesh']['vertices']
print('installed', tailor.__file__)
" ${PREFIX} ${SCENE} WORKING_DIRECTORY ${PREFIX} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    set(failure "the installed package did not import and run" PARENT_SCOPE)
    return()
  endif()
endfunction()

# The scratch folder goes whether the checks pass or not.
set(failure "")
check_install()
file(REMOVE_RECURSE ${SCRATCH})
if(failure)
  message(FATAL_ERROR "${failure}")
endif()
