# python.install: `cmake --install --component python` into a scratch PREFIX, then the package
# imports from PREFIX/PACKAGE_DIR (not from the build tree: it runs in PREFIX, as python -c puts
# the current folder first on sys.path) and solves SCENE.
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --component python
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "cmake --install --component python failed")
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
  message(FATAL_ERROR "the installed package did not import and run")
endif()
