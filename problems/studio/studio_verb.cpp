#include "problems/studio/studio_verb.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <thread>

#include "problems/fem/scene.hpp"
#include "problems/studio/http_server.hpp"
#include "problems/studio/parent_watch.hpp"
#include "problems/studio/studio_messages.hpp"

namespace tailor::studio {
namespace fs = std::filesystem;

fs::path find_studio_assets() {
  if (const char* given = std::getenv("TAILOR_STUDIO_ASSETS"))
    return fs::exists(fs::path(given) / "index.html") ? fs::path(given) : fs::path();
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  if (error) return {};
  const fs::path assets = program.parent_path().parent_path() / "share" / "tailor" / "studio";
  return fs::exists(assets / "index.html", error) ? assets : fs::path();
}

namespace {

struct StudioFlags {
  int port = 0;
  bool exit_on_stdin_eof = false;
  bool exit_with_parent = false;
};

int run_studio(const VerbArguments& args, const StudioFlags& flags, std::ostream& out) {
  const fs::path assets = find_studio_assets();
  if (assets.empty())
    throw UsageError(
        "the studio's page is not built: run 'bash scripts/build-studio-web.sh' (needs Node and npm), or set "
        "TAILOR_STUDIO_ASSETS to a folder with its index.html");
  const std::string path = args.scene.value();
  std::unique_ptr<DesignSession> design;
  fs::path folder;
  std::string title;
  if (fs::is_directory(path)) {
    folder = path;
    title = fs::path(path).filename().string();
  } else {
    const SceneFile file = read_scene_file(path);
    folder = output_folder(file, args);
    title = fs::path(path).stem().string();
    const nlohmann::json& inverse = file.document.contains("inverse") ? file.document["inverse"] : nlohmann::json();
    if (inverse.is_object() && inverse.contains("design") && inverse["design"].is_object() &&
        inverse["design"].contains("reduction")) {
      out << "tailor studio: precomputing the reduced design of " << path << " ..." << std::endl;
      design = std::make_unique<DesignSession>(read_scene(path));
    }
  }
  StudioMessages messages(std::move(design), folder, title);
  StudioServerOptions options;
  options.port = flags.port;
  options.assets = assets;
  StudioServer server(endpoints(messages), options);
  server.bind();
  out << "tailor studio: " << server.url() << "\n"
      << "(serving " << folder.string() << "; only requests with this URL's token are answered; Ctrl-C stops)"
      << std::endl;
  // Whoever started the program going away stops the server; a computation still running 10 s
  // later (the server waits for its requests) ends with the process.
  ParentWatchOptions watched;
  watched.end_of_file_fd = flags.exit_on_stdin_eof ? 0 : -1;
  watched.parent = flags.exit_with_parent;
  const ParentWatch watch(watched, [&server](const std::string& reason) {
    std::cerr << "tailor studio: stopping: " << reason << std::endl;
    server.stop();
    std::thread([] {
      std::this_thread::sleep_for(std::chrono::seconds(10));
      std::_Exit(kExitSuccess);
    }).detach();
  });
  server.serve();
  return kExitSuccess;
}

}  // namespace

Verb studio_verb() {
  auto flags = std::make_shared<StudioFlags>();
  Verb verb;
  verb.name = "studio";
  verb.synopsis = "studio SCENE_OR_OUT_DIR [--port N] [--exit-on-stdin-eof] [--exit-with-parent]";
  verb.help =
      "serve a local web page (127.0.0.1, a per-run token in its URL): a handle scene with\n"
      "inverse.design.reduction opens the interactive design (drag the handles' targets);\n"
      "another scene opens the viewer of its output folder, a folder the viewer of that folder\n"
      "(docs/studio.md).";
  verb.writes_output = false;
  verb.options = [flags](CLI::App& command, VerbArguments& args) {
    command.add_option("--port", flags->port, "the port to listen on (default: a free one)")->type_name("N")->check(
        CLI::Range(0, 65535));
    command.add_flag("--exit-on-stdin-eof", flags->exit_on_stdin_eof,
                     "stop when standard input reaches its end (the starter's pipe closed: it ended)");
    command.add_flag("--exit-with-parent", flags->exit_with_parent, "stop when the parent process ends");
    command.add_option("--out", args.out_dir, "a scene's output folder (default: out/<scene stem>)")->type_name("DIR");
  };
  verb.run = [flags](const VerbArguments& args, std::ostream& out) { return run_studio(args, *flags, out); };
  return verb;
}

}  // namespace tailor::studio
