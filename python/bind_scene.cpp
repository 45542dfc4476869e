// Scenes and the command line's verbs: tailor._tailor.Scene. Each verb does what `tailor <verb>`
// does with the same scene, given as a file or as JSON (the same functions for static and
// dynamic scenes, the command line's own handler for the other kinds) and returns the exit code
// and the result fields as NumPy views; the Python layer adds the report.json it wrote.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "problems/fem/commands.hpp"
#include "problems/fem/dynamic_commands.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/modes_command.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/meshless/meshless_runs.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "python_stream.hpp"

namespace py = pybind11;

namespace tailor::python {

std::string SceneDocument::kind() const { return recognise_scene_kind(file.document).name; }

namespace {

constexpr int kSuccess = 0, kFailure = 1;

SceneDocument from_file(const std::string& path) { return {read_scene_file(path)}; }

// A document given as JSON text: `directory` is where its relative paths start ("": the current
// folder).
SceneDocument from_json(const std::string& text, const std::string& source, const std::string& directory) {
  return {scene_from_text(text, source, directory)};
}

bool is_mesh_scene(const std::string& kind) { return kind == "static" || kind == "dynamic"; }

// The command line's handler for `verb` on a scene of another kind (rods, rigid bodies, cells,
// ...), on the document as given (a file or JSON).
int dispatch(const SceneDocument& doc, const std::string& verb, VerbArguments args, std::ostream& out) {
  const SceneKind& kind = recognise_scene_kind(doc.file.document);
  const KindVerb* entry = kind.find_verb(verb);
  if (!entry)
    throw SceneError(doc.file.source + ": '" + verb + "' does not apply to a " + kind.name +
                     " scene; its verbs: " + kind.verb_list());
  args.verb = verb;
  if (!doc.file.path.empty()) args.scene = doc.file.path;
  apply_thread_flags(args, std::nullopt);
  return entry->handler(doc.file, args, out);
}

void require_verb(const SceneDocument& doc, const std::string& verb) {
  const SceneKind& kind = recognise_scene_kind(doc.file.document);
  if (!kind.find_verb(verb))
    throw SceneError(doc.file.source + ": '" + verb + "' does not apply to a " + kind.name +
                     " scene; its verbs: " + kind.verb_list());
}

template <class T>
std::shared_ptr<const void> owner(const std::shared_ptr<T>& p) {
  return std::static_pointer_cast<const void>(p);
}

// A meshless solid's fields (problems/meshless/meshless_fields.hpp) as views kept alive by `keep`.
void add_meshless_fields(py::dict& fields, const std::shared_ptr<const void>& keep, const MeshlessFields& f) {
  for (const auto& [name, array] : {std::pair{"rest_positions", &f.rest_positions}, {"displacement", &f.displacement},
                                    {"positions", &f.positions}, {"coefficient_displacement", &f.coefficient_displacement},
                                    {"samples", &f.samples}, {"sample_displacement", &f.sample_displacement}})
    fields[name] = view(keep, *array);
  fields["youngs_modulus"] = view(keep, f.youngs_modulus);
}

// The meshless verbs' options for a document: its name, its folder, the output folder, and the
// command line's thread settings applied (as a verb without thread flags).
MeshlessVerbOptions meshless_verb_options(const SceneDocument& doc, const std::string& out_dir) {
  MeshlessVerbOptions options;
  options.name = doc.file.name();
  options.directory = doc.file.directory();
  options.out_dir = out_dir;
  apply_thread_flags(VerbArguments{}, std::nullopt);
  return options;
}

// youngs_modulus and poisson_ratio: per-element values replacing the scene's (static scenes).
py::tuple simulate(const SceneDocument& doc, const std::string& out_dir, py::object log,
                   std::optional<Eigen::VectorXd> youngs_modulus,
                   std::optional<Eigen::VectorXd> poisson_ratio) {
  const std::string kind = doc.kind();
  MaterialOverrides overrides;
  if (youngs_modulus) overrides.youngs_modulus = std::move(*youngs_modulus);
  if (poisson_ratio) overrides.poisson_ratio = std::move(*poisson_ratio);
  if (!overrides.empty() && kind != "static")
    throw std::invalid_argument(doc.file.source + ": per-element youngs_modulus and poisson_ratio apply to " +
                                "static FEM scenes; this is a " + kind + " scene");
  PythonStream out(std::move(log), /*check_signals=*/true);
  py::dict fields;
  int code = kFailure;
  if (kind == "static") {
    auto run = without_gil([&] {
      const Scene scene = parse_mesh_scene(doc);
      return std::make_shared<SimulateRun>(simulate_scene(scene, overrides, out_dir, &out));
    });
    const auto keep = owner(run);
    fields["displacement"] = view(keep, run->solution.displacement);
    fields["positions"] = view(keep, run->solution.positions);
    fields["stresses"] = view(keep, run->solution.stresses);
    fields["youngs_modulus"] = view(keep, run->setup.youngs_modulus);
    fields["poisson_ratio"] = view(keep, run->setup.poisson_ratio);
    fields["density"] = view(keep, run->setup.density);
    fields["rest_positions"] = view(keep, run->setup.mesh.rest_positions);
    fields["elements"] = view(keep, run->setup.mesh.elements);
    code = run->solution.converged ? kSuccess : kFailure;
  } else if (kind == "meshless") {
    auto run = without_gil([&] {
      return std::make_shared<MeshlessSimulation>(
          simulate_meshless(doc.file.node(), meshless_verb_options(doc, out_dir), &out));
    });
    add_meshless_fields(fields, owner(run), run->fields);
    code = run->converged ? kSuccess : kFailure;
  } else if (kind == "dynamic") {
    code = without_gil([&] {
      const Scene scene = parse_mesh_scene(doc);
      return simulate_dynamic_scene(scene, out_dir, &out).completed ? kSuccess : kFailure;
    });
  } else {
    code = without_gil([&] {
      VerbArguments args;
      args.out_dir = out_dir;
      return dispatch(doc, "simulate", args, out);
    });
  }
  out.flush();
  return py::make_tuple(code, fields);
}

py::tuple modes(const SceneDocument& doc, const std::string& out_dir, int count, py::object log) {
  require_verb(doc, "modes");
  PythonStream out(std::move(log), /*check_signals=*/true);
  if (doc.kind() == "meshless") {
    auto run = without_gil([&] {
      MeshlessVerbOptions options = meshless_verb_options(doc, out_dir);
      options.count = count;
      return std::make_shared<MeshlessModes>(compute_meshless_modes(doc.file.node(), options, &out));
    });
    const auto keep = owner(run);
    py::dict fields;
    for (const auto& [name, array] : {std::pair{"frequencies", &run->frequencies}, {"eigenvalues", &run->eigenvalues},
                                      {"damping_ratios", &run->damping_ratios}})
      fields[name] = view(keep, *array);
    for (const auto& [name, array] : {std::pair{"modes", &run->node_modes}, {"rest_positions", &run->rest_positions},
                                      {"samples", &run->samples}, {"sample_modes", &run->sample_modes}})
      fields[name] = view(keep, *array);
    fields["rigid_modes"] = run->rigid_modes;
    out.flush();
    return py::make_tuple(kSuccess, fields);
  }
  if (!is_mesh_scene(doc.kind())) {
    // Another kind's own handler: its report and files, no fields.
    const int code = without_gil([&] {
      VerbArguments args;
      args.out_dir = out_dir;
      args.count = count;
      return dispatch(doc, "modes", args, out);
    });
    out.flush();
    return py::make_tuple(code, py::dict());
  }
  auto run = without_gil([&] {
    const Scene scene = parse_mesh_scene(doc);
    return std::make_shared<ModesRun>(modes_scene(scene, count, out_dir, &out));
  });
  const auto keep = owner(run);
  py::dict fields;
  fields["frequencies"] = view(keep, run->modes.frequencies);
  fields["eigenvalues"] = view(keep, run->modes.eigenvalues);
  fields["modes"] = view(keep, run->modes.modes);
  fields["rigid_modes"] = view(keep, run->modes.rigid_modes);
  out.flush();
  return py::make_tuple(kSuccess, fields);
}

py::tuple gradcheck(const SceneDocument& doc, const std::string& out_dir, std::optional<unsigned> seed,
                    bool hessian, py::object log) {
  const std::string kind = doc.kind();
  PythonStream out(std::move(log), /*check_signals=*/true);
  py::dict fields;
  const int code = without_gil([&] {
    if (!is_mesh_scene(kind)) {
      VerbArguments args;
      args.out_dir = out_dir;
      args.seed = seed;
      args.hessian = hessian;
      return dispatch(doc, "gradcheck", args, out);
    }
    const Scene scene = parse_mesh_scene(doc);
    const GradcheckRun run = kind == "dynamic" && !scene.inverse
                                 ? gradcheck_dynamic_scene(scene, out_dir, seed.value_or(1), &out)
                                 : gradcheck_scene(scene, out_dir, {seed, hessian}, &out);
    return run.passed() ? kSuccess : kFailure;
  });
  out.flush();
  return py::make_tuple(code, fields);
}

// The optimizer stops itself on Ctrl-C (its own SIGINT handler while it runs) and writes its
// report; before and after it, a Ctrl-C raises KeyboardInterrupt at the next line of output.
py::tuple run(const SceneDocument& doc, const std::string& out_dir, py::object log, bool progress,
              std::optional<int> checkpoint_every, std::optional<std::string> resume) {
  const std::string kind = doc.kind();
  PythonStream out(std::move(log), /*check_signals=*/true);
  py::dict fields;
  int code = kFailure;
  if (is_mesh_scene(kind)) {
    require_verb(doc, "run");
    auto result = without_gil([&] {
      const Scene scene = parse_mesh_scene(doc);
      return std::make_shared<InverseRun>(
          run_inverse_scene(scene, out_dir, &out, progress ? &out : nullptr, {checkpoint_every, resume}));
    });
    const auto keep = owner(result);
    fields["design"] = view(keep, result->result.z);
    fields["design_values"] = view(keep, result->design_values);
    fields["youngs_modulus"] = view(keep, result->youngs_modulus);
    fields["displacement"] = view(keep, result->solution.displacement);
    fields["rest_positions"] = view(keep, result->problem->setup.mesh.rest_positions);
    fields["elements"] = view(keep, result->problem->setup.mesh.elements);
    fields["status"] = to_string(result->result.status);
    code = result->result.converged() ? kSuccess : kFailure;
  } else if (kind == "meshless" && !checkpoint_every && !resume) {  // the handler refuses those flags
    auto result = without_gil([&] {
      MeshlessVerbOptions options = meshless_verb_options(doc, out_dir);
      options.progress = progress ? &out : nullptr;
      return std::make_shared<MeshlessRun>(run_meshless(doc.file.node(), options, &out));
    });
    add_meshless_fields(fields, owner(result), result->fields);
    fields["design"] = view(owner(result), result->design);
    fields["status"] = result->status;
    code = result->succeeded ? kSuccess : kFailure;
  } else {
    code = without_gil([&] {
      VerbArguments args;
      args.out_dir = out_dir;
      args.quiet = !progress;
      args.checkpoint_every = checkpoint_every;
      args.resume = resume;
      return dispatch(doc, "run", args, out);
    });
  }
  out.flush();
  return py::make_tuple(code, fields);
}

// `tailor homogenize` on a periodic cell: the command line's handler.
py::tuple homogenize(const SceneDocument& doc, const std::string& out_dir, py::object log) {
  PythonStream out(std::move(log), /*check_signals=*/true);
  const int code = without_gil([&] {
    VerbArguments args;
    args.out_dir = out_dir;
    return dispatch(doc, "homogenize", args, out);
  });
  out.flush();
  return py::make_tuple(code, py::dict());
}

int check(const SceneDocument& doc, unsigned seed, py::object log) {
  const std::string kind = doc.kind();
  PythonStream out(std::move(log), /*check_signals=*/true);
  const int code = without_gil([&] {
    if (!is_mesh_scene(kind)) {
      VerbArguments args;
      args.seed = seed;
      return dispatch(doc, "check", args, out);
    }
    return check_scene(parse_mesh_scene(doc), seed, &out) ? kSuccess : kFailure;
  });
  out.flush();
  return code;
}

}  // namespace

// The static or dynamic scene (docs/scenes.md), named as the command line names it, with its
// solver.threads applied as the command line does.
Scene parse_mesh_scene(const SceneDocument& doc) {
  Scene scene = parse_scene(doc.file.node(), doc.file.directory());
  scene.name = doc.file.name();
  apply_thread_flags(VerbArguments{}, scene.solver.threads);
  return scene;
}

void bind_scene(py::module_& m) {
  py::class_<SceneDocument>(m, "Scene", "A scene document (docs/scenes.md), as the command line reads it.")
      .def_static("from_file", &from_file, py::arg("path"))
      .def_static("from_json", &from_json, py::arg("text"), py::arg("source") = "(scene)",
                  py::arg("directory") = "")
      .def_property_readonly("kind", &SceneDocument::kind)
      .def_property_readonly("source", [](const SceneDocument& s) { return s.file.source; })
      .def_property_readonly("directory", [](const SceneDocument& s) { return s.file.directory(); })
      .def_property_readonly("path", [](const SceneDocument& s) { return s.file.path; })
      .def_property_readonly("text", [](const SceneDocument& s) { return dump_json(s.file.document); })
      .def("name", [](const SceneDocument& doc) { return doc.file.name(); })
      .def("simulate", &simulate, py::arg("out_dir"), py::arg("log") = py::none(),
           py::arg("youngs_modulus") = py::none(), py::arg("poisson_ratio") = py::none())
      .def("modes", &modes, py::arg("out_dir"), py::arg("count") = 10, py::arg("log") = py::none())
      .def("gradcheck", &gradcheck, py::arg("out_dir"), py::arg("seed") = py::none(),
           py::arg("hessian") = false, py::arg("log") = py::none())
      .def("run", &run, py::arg("out_dir"), py::arg("log") = py::none(), py::arg("progress") = true,
           py::arg("checkpoint_every") = py::none(), py::arg("resume") = py::none())
      .def("homogenize", &homogenize, py::arg("out_dir"), py::arg("log") = py::none())
      .def("check", &check, py::arg("seed") = 1, py::arg("log") = py::none());
}

}  // namespace tailor::python
