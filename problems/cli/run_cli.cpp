#include "problems/cli/run_cli.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "forward/mesh/mesh.hpp"
#include "problems/cli/flag_checks.hpp"
#include "problems/output_folder.hpp"
#include "problems/output_process.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "tailor_version.hpp"

namespace tailor {
namespace {

// `text` with every line indented by `indent` spaces.
std::string indented(const std::string& text, int indent) {
  std::string result;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    result += std::string(static_cast<std::size_t>(indent), ' ') + line + "\n";
  return result;
}

// "-h, --help" / "--out DIR": how the usage text names an option.
std::string option_label(const CLI::Option& option) {
  std::string label;
  for (const std::string& name : option.get_snames()) label += (label.empty() ? "-" : ", -") + name;
  for (const std::string& name : option.get_lnames()) label += (label.empty() ? "--" : ", --") + name;
  // get_type_name() appends the validator's description ("N:INT in [1 - 4096]").
  const std::string type = option.get_type_name().substr(0, option.get_type_name().find(':'));
  if (option.get_type_size() != 0 && !type.empty()) label += " " + type;
  return label;
}

// The non-positional options of `command`, one per line with its description.
std::string option_lines(const CLI::App& command) {
  std::ostringstream s;
  for (const CLI::Option* option : command.get_options()) {
    if (option->get_positional()) continue;
    const std::string label = option_label(*option);
    s << "  " << std::left << std::setw(26) << label;
    if (label.size() > 25) s << "\n" << std::string(28, ' ');
    s << option->get_description() << "\n";
  }
  return s.str();
}

std::string top_usage(const CLI::App& app) {
  std::ostringstream s;
  s << "usage: tailor <verb> [scene.json] [flags]\n\nverbs:\n";
  for (const Verb* verb : registered_verbs()) s << "  " << verb->synopsis << "\n" << indented(verb->help, 6);
  s << "\nscene kinds (a scene file is of the first kind that matches its top-level JSON):\n";
  for (const SceneKind* kind : registered_scene_kinds()) {
    s << "  " << std::left << std::setw(15) << kind->name << ' ' << kind->recognised_by << "\n";
    s << std::string(18, ' ') << "verbs: " << kind->verb_list() << "\n";
  }
  s << "\nflags of every verb:\n"
    << option_lines(app)
    << "\nexit codes: 0 success, 1 solve, check or optimization failed (or did not converge),\n"
       "2 bad input or usage.\n"
       "'tailor <verb> --help' shows a verb's flags and what it does on each kind of scene.\n"
       "The scene format is described in docs/scenes.md.\n";
  return s.str();
}

std::string verb_usage(const Verb& verb, const CLI::App& command, const CLI::App& app) {
  std::ostringstream s;
  s << "usage: tailor " << verb.synopsis << "\n\n" << indented(verb.help, 2) << "\nscene kinds:\n";
  for (const SceneKind* kind : registered_scene_kinds())
    if (const KindVerb* entry = kind->find_verb(verb.name)) {
      s << "  " << std::left << std::setw(15) << kind->name << ' ' << kind->recognised_by << "\n";
      if (!entry->note.empty()) s << std::string(18, ' ') << entry->note << "\n";
    }
  s << "\nflags:\n" << option_lines(command) << option_lines(app);
  return s.str();
}

// CLI11's parse errors in tailor's words: the ones a user meets name the flag and what it needs
// (e.g. "--out: At Most 1 required but received 2" becomes "--out takes one value; it was given
// 2"); others pass unchanged.
std::string plain_parse_error(const std::string& what) {
  static const std::regex at_most(R"(^(\S+): At Most (\d+) required but received (\d+)$)");
  static const std::regex missing(R"(^(\S+): (\d+) required (\S+) missing$)");
  static const std::regex at_least(R"(^(\S+): At least (\d+) required but received (\d+)$)");
  std::smatch m;
  if (std::regex_match(what, m, at_most))
    return m[1].str() + (m[2] == "1" ? " takes one value" : " takes at most " + m[2].str() + " values") +
           "; it was given " + m[3].str() + " (give it once; quote a path with spaces)";
  if (std::regex_match(what, m, missing) || std::regex_match(what, m, at_least))
    return m[1].str() + " needs a value";
  return what;
}

class Cli {
 public:
  Cli(std::ostream& out, std::ostream& err) : out_(out), err_(err) {
    app_.set_help_flag();
    app_.allow_extras();
    app_.require_subcommand(0, 1);
    app_.add_option("--threads", args_.threads,
                    "threads for tailor's loops and for BLAS (default: one per core)")
        ->type_name("N")
        ->check(cli::integer_in(1, 4096));
    app_.add_option("--factorization-threads", args_.factorization_threads,
                    "CHOLMOD's own OpenMP loops: 1 serialized (default, fastest\n" + std::string(28, ' ') +
                        "measured), 0 as CHOLMOD was built; overrides solver.threads")
        ->type_name("1|0")
        ->check(cli::integer_in(0, 1));
    app_.add_flag("-h,--help", help_, "show this message (after a verb: the verb's)");
    app_.add_flag("--version", version_, "print the version");
    for (const Verb* verb : registered_verbs()) {
      CLI::App* command = app_.add_subcommand(verb->name, verb->help);
      command->set_help_flag();
      command->allow_extras();
      command->fallthrough();  // the flags of every verb may follow the verb
      command->add_option("scene", args_.scene, "the scene file");
      if (verb->options) verb->options(*command, args_);
      commands_.push_back({verb, command});
    }
  }

  int run(int argc, const char* const* argv) {
    for (int i = 0; i < argc; ++i) command_line_ += (i ? " " : "") + std::string(argv[i] ? argv[i] : "");
    try {
      app_.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return usage_error(plain_parse_error(e.what()));
    }
    find_verb_on_command_line();
    if (version_) {
      out_ << "tailor " << version_string << "\n";
      return kExitSuccess;
    }
    const std::vector<std::string> extra = app_.remaining(/*recurse=*/true);
    if (!verb_) {
      if (help_) return (out_ << top_usage(app_), kExitSuccess);
      if (extra.empty()) return usage_error("no verb given");
      if (extra[0].rfind('-', 0) == 0) return usage_error("unknown option '" + extra[0] + "'");
      return usage_error("unknown verb '" + extra[0] + "'");
    }
    const std::string& name = verb_->name;
    if (!extra.empty()) {
      if (extra[0].rfind('-', 0) == 0)
        return usage_error("unknown option '" + extra[0] + "' for '" + name + "'");
      return usage_error("more than one scene given ('" + args_.scene.value_or("") + "', '" + extra[0] +
                         "')");
    }
    if (help_) return (out_ << verb_usage(*verb_, *command_, app_), kExitSuccess);
    if (verb_->needs_scene && !args_.scene) return usage_error("'" + name + "' needs a scene file");
    args_.verb = name;
    apply_thread_flags(args_, std::nullopt);
    std::optional<OutputFolder> folder;  // claimed before the handler, held until it returns
    // Input that is refused releases the folder and removes it when this run created it empty.
    const auto bad_input = [&](const std::string& message) {
      if (folder) folder->release_and_tidy();
      err_ << "tailor: error: " << message << "\n";
      return kExitBadInput;
    };
    try {
      if (verb_->run) return verb_->run(args_, out_);
      const SceneFile file = args_.scene ? read_scene_file(*args_.scene) : SceneFile{};
      const SceneKind& kind = args_.scene ? recognise_scene_kind(file.document) : default_scene_kind();
      const KindVerb* entry = kind.find_verb(name);
      if (!entry) {
        err_ << "tailor: '" << name << "' does not apply to "
             << (args_.scene ? *args_.scene + ", a " + kind.name + " scene"
                             : std::string("a run without a scene file"))
             << "; its verbs: " << kind.verb_list()
             << "\nRun 'tailor --help' for the verbs of each kind of scene.\n";
        return kExitBadInput;
      }
      // A --resume folder that does not exist is not created: the handler refuses it, naming it.
      const bool missing_resume = args_.resume && !std::filesystem::exists(*args_.resume);
      if (verb_->writes_output && writes_output() && !missing_resume)
        folder.emplace(output_folder(file, args_), command_line_);
      return entry->handler(file, args_, out_);
    } catch (const UsageError& e) {
      if (folder) folder->release_and_tidy();
      return usage_error(e.what());
    } catch (const SceneError& e) {
      return bad_input(e.what());
    } catch (const MeshError& e) {
      return bad_input(e.what());
    } catch (const std::exception& e) {
      err_ << "tailor: error: " << e.what() << "\n";
      return kExitFailure;
    }
  }

 private:
  // The usage of the verb on the command line (else of tailor) after the message.
  int usage_error(const std::string& what) {
    find_verb_on_command_line();
    err_ << "tailor: " << what << "\n\n" << (verb_ ? verb_usage(*verb_, *command_, app_) : top_usage(app_));
    return kExitBadInput;
  }

  void find_verb_on_command_line() {
    for (const auto& [verb, command] : commands_)
      if (command->parsed()) verb_ = verb, command_ = command;
  }

  std::ostream& out_;
  std::ostream& err_;
  CLI::App app_{"tailor: inverse design of deformable objects", "tailor"};
  VerbArguments args_;
  bool help_ = false, version_ = false;
  std::string command_line_;  // how a second run into the same folder names this one
  std::vector<std::pair<const Verb*, CLI::App*>> commands_;
  const Verb* verb_ = nullptr;
  CLI::App* command_ = nullptr;
};

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  Cli cli(out, err);
  return cli.run(argc, argv);
}

int run_cli(int argc, const char* const* argv) { return run_cli(argc, argv, std::cout, std::cerr); }

}  // namespace tailor
