#pragma once
// The verbs of the `tailor` command line and the kinds of scene file they act on, in one
// registration table. A scene file is read and parsed once; its kind is the first registered
// kind whose `recognises` accepts the top-level JSON; the kind names the verbs it supports, each
// with its handler. A verb the kind does not support is a usage error (exit 2) that lists the
// verbs it does support, and the usage text's lists of verbs and kinds are made from this table.
//
// tailor's own verbs and kinds are registered in problems/builtin_scene_kinds.cpp: adding a kind
// is one entry there (plus the kind's own files). A program can register its own verbs and kinds
// before it calls tailor::run_cli (problems/cli/run_cli.hpp); they are recognised before
// tailor's own kinds.
#include <functional>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/solve/threads.hpp"

namespace CLI {
class App;  // CLI11 (include <CLI/CLI.hpp> to define a verb's options)
}

namespace tailor {

class SceneNode;  // problems/scene_node.hpp

// What the command line gave the verb. Per-verb flags: add a field here and bind it to its
// flag in the verb's `options` (problems/builtin_scene_kinds.cpp).
struct VerbArguments {
  std::string verb;
  std::optional<std::string> scene;     // the scene file (a positional argument)
  std::optional<std::string> out_dir;   // --out DIR
  std::optional<unsigned> seed;         // --seed N (check, gradcheck)
  bool hessian = false;                 // --hessian (gradcheck)
  bool quiet = false;                   // --quiet (run)
  int count = 10;                       // --count N (modes)
  std::optional<int> checkpoint_every;  // --checkpoint-every K (run)
  std::optional<std::string> resume;    // --resume DIR (run): the checkpoint to continue from
  // Every verb: --threads N, --factorization-threads 1|0 (see apply_thread_flags).
  std::optional<int> threads, factorization_threads;

  std::string out_dir_or(const std::string& fallback) const { return out_dir.value_or(fallback); }
};

// A handler's usage error (e.g. a flag its kind cannot honour): exit 2 with the verb's usage.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The scene a verb acts on, read and parsed once: a file (`path`; `source` is the path), or a
// document given in memory (no path; `source` names it in messages, `base_directory` is where
// its relative paths start). Without a scene (the command line given no scene file) `source` is
// empty, and the default kind runs its built-in scene.
struct SceneFile {
  std::string path;            // the file; empty for a document given in memory
  std::string source;          // the scene's name in messages: the path for a file; empty: no scene
  nlohmann::json document;     // the parsed top-level value
  std::string base_directory;  // a document in memory: the folder of its relative paths ("": the current one)

  bool given() const { return !source.empty(); }
  // The document with its source: every kind's parser takes this (errors name source and key path).
  SceneNode node() const;
  std::string directory() const;  // the folder that relative paths in the scene start from
  std::string stem() const;       // the file name without its extension ("scene" in memory)
  std::string name() const;       // the scene's "name" when a non-empty string, else stem()
  // Every kind's default output folder: out/<name()>.
  std::string default_out_dir() const;
};

// A scene file, read and parsed. SceneError naming the file when it is a folder, cannot be read,
// or is not JSON (with the position; problems/scene_node.hpp, read_scene_document).
SceneFile read_scene_file(const std::string& path);
// A document in memory (its text, or the parsed value): `source` names it in messages ("(scene)"
// when empty), `directory` is where its relative paths start.
SceneFile scene_from_text(const std::string& json_text, const std::string& source,
                          const std::string& directory = "");
SceneFile scene_from_document(nlohmann::json document, const std::string& source,
                              const std::string& directory = "");

// The folder a verb writes into: --out DIR; else, for `run --resume DIR`, DIR (or the
// checkpoint file's folder); else the scene's default_out_dir(), out/cantilever for the built-in
// scene run without a scene file. Every kind's handler writes there.
std::string output_folder(const SceneFile& file, const VerbArguments& args);

// The CLI's exit codes: success, a solve, check or optimization that failed, bad input.
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;

// A verb's work on one kind of scene. Returns the exit code: 0 success, 1 the solve, check or
// optimization failed. Writes its log to `out`. Throws SceneError or MeshError for bad input
// (exit 2); any other exception is reported and exits with 1.
using VerbHandler = std::function<int(const SceneFile& scene, const VerbArguments& args, std::ostream& out)>;

struct Verb {
  std::string name;      // e.g. "simulate"
  std::string synopsis;  // e.g. "simulate [scene.json] [--out DIR]"
  std::string help;      // what it does; lines separated by '\n', indented by the usage text
  // Without a scene file the verb is a usage error, unless false: then the default kind runs it.
  bool needs_scene = true;
  // Adds the verb's own flags to its CLI11 subcommand, bound to fields of `args`.
  std::function<void(CLI::App& command, VerbArguments& args)> options;
  // Whether the verb writes files into output_folder(): the command line then claims that folder
  // before the handler runs (problems/output_folder.hpp: created, checked, locked).
  bool writes_output = true;
  // A verb that is not dispatched on a scene kind (its argument need not be a scene file, e.g.
  // `studio` takes a folder too) runs this instead; empty for the others.
  std::function<int(const VerbArguments& args, std::ostream& out)> run = nullptr;
};

// One verb a kind supports.
struct KindVerb {
  std::string verb;  // the name of a registered verb
  VerbHandler handler;
  std::string note;  // what the verb does on this kind (shown by `tailor <verb> --help`)
};

struct SceneKind {
  std::string name;           // e.g. "rigid_bodies"
  std::string recognised_by;  // for the usage text, e.g. "a \"rigid_bodies\" section"
  std::function<bool(const nlohmann::json& document)> recognises;
  std::vector<KindVerb> verbs;

  const KindVerb* find_verb(const std::string& verb) const;
  std::string verb_list() const;  // "simulate, gradcheck"
};

// Registration. Throws std::logic_error for a duplicate or empty name, a kind without
// `recognises` or verbs, a kind verb without a handler, or a verb that is not registered
// (register a program's own verbs before the kinds that use them).
void register_verb(Verb verb);
void register_scene_kind(SceneKind kind);

// The registered verbs, in registration order (tailor's own first). The entries stay where
// they are when more are registered.
std::vector<const Verb*> registered_verbs();
const Verb* find_verb(const std::string& name);
// The registered kinds in the order they are tried: a program's own, then tailor's; the last
// is the default kind, which recognises every scene and runs the verbs given no scene file.
std::vector<const SceneKind*> registered_scene_kinds();
const SceneKind& recognise_scene_kind(const nlohmann::json& document);
const SceneKind& default_scene_kind();

// The thread configuration for a run: the scene's solver.threads when given (else the current
// settings), with --threads and --factorization-threads on top.
void apply_thread_flags(const VerbArguments& args, const std::optional<ThreadSettings>& scene_threads);

// tailor's own verbs and kinds, in order (problems/builtin_scene_kinds.cpp); the registry
// starts with them.
std::vector<Verb> builtin_verbs();
std::vector<SceneKind> builtin_scene_kinds();

}  // namespace tailor
