#pragma once
// The parts of the module tailor._tailor (module.cpp puts them together).
#include <pybind11/pybind11.h>

#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

#include "adjoint/reduced_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/scene.hpp"
#include "problems/scene_kinds.hpp"
#include "python_stream.hpp"

namespace tailor::python {

// A scene document as the command line reads it (problems/scene_kinds.hpp): the JSON, the name
// it goes by in messages (the file's path, or what the caller gave), the folder its relative
// paths start from, and the file it came from (empty for a document given as JSON).
struct SceneDocument {
  SceneFile file;
  std::string kind() const;  // the registered scene kind that recognises it ("static", "dynamic", ...)
};

void bind_scene(pybind11::module_& m);
void bind_functional(pybind11::module_& m);
void bind_rod_functional(pybind11::module_& m);
void bind_dynamic_functional(pybind11::module_& m);
void bind_cell_functional(pybind11::module_& m);
void bind_meshless_functional(pybind11::module_& m);

// The static or dynamic scene (docs/scenes.md), named as the command line names it, with its
// solver.threads applied as the command line does.
Scene parse_mesh_scene(const SceneDocument& doc);

// What the functionals return as dicts: a Taylor test (rows, rates, status, table), the solve
// counters, and the optimizer section of the scene.
pybind11::dict taylor_result_dict(const TaylorTestResult& r);
pybind11::dict counters_dict(const FunctionalCounters& c);
pybind11::dict optimizer_dict(const OptimizerOptions& o);

// Runs `body` with the GIL released; a pending Python exception (Ctrl-C, a failing write()) raised
// from inside comes back as that exception.
template <class Body>
auto without_gil(Body&& body) {
  try {
    pybind11::gil_scoped_release release;
    return body();
  } catch (const PythonErrorPending&) {
    throw pybind11::error_already_set();
  }
}

// Runs `body` with the GIL released and `mutex` held: Python threads sharing a functional take turns.
template <class Body>
auto locked(std::mutex& mutex, Body&& body) {
  return without_gil([&] {
    const std::lock_guard<std::mutex> lock(mutex);
    return body();
  });
}

// Throws std::invalid_argument naming `source` when `v` (called `name`) has not `size` entries.
void check_design_size(const std::string& source, const Vector& v, int size, const char* name);

}  // namespace tailor::python
