// tailor._tailor: the compiled part of the Python package tailor (python/tailor/ is the rest).
// Errors: bad input (SceneError, MeshError, std::invalid_argument) is a ValueError -- SceneError
// and MeshError as their own subclasses -- and the failures of a run (std::runtime_error, such
// as an output that cannot be written or a forward solve that failed) a RuntimeError, each with
// the C++ message (key path, file and line). A verb's option that the kind of scene cannot
// honour (UsageError) is a ValueError too.
#include <pybind11/pybind11.h>

#include "adjoint/reduced_functional.hpp"
#include "bindings.hpp"
#include "forward/mesh/mesh.hpp"
#include "problems/fem/scene.hpp"
#include "problems/scene_kinds.hpp"
#include "tailor_version.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_tailor, m) {
  m.doc() = "tailor's scenes, verbs and reduced functionals (see docs/python.md)";
  m.attr("__version__") = tailor::version_string;
  // pybind11 tries the translators registered last first: the subclasses go after their bases.
  py::register_exception<tailor::EvaluationError>(m, "EvaluationError", PyExc_RuntimeError);
  py::register_exception<tailor::SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<tailor::MeshError>(m, "MeshError", PyExc_ValueError);
  // A Python exception raised inside a call (Ctrl-C, a log whose write() failed) is already set.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tailor::python::PythonErrorPending&) {
    } catch (const tailor::UsageError& e) {  // a verb's option its kind of scene cannot honour
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  tailor::python::bind_scene(m);
  tailor::python::bind_functional(m);
  tailor::python::bind_rod_functional(m);
  tailor::python::bind_dynamic_functional(m);
  tailor::python::bind_cell_functional(m);
  tailor::python::bind_meshless_functional(m);
}
