// The command line's registration table (problems/scene_kinds.hpp) seen from outside: a program
// registers a toy verb and scene kind, then runs tailor::run_cli in-process. Also the usage
// errors (exit 2) for bad flag values and for verbs a scene's kind does not support.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/temp_folder.hpp"
#include "problems/cli/run_cli.hpp"
#include "problems/scene_kinds.hpp"

namespace tailor::cli_registry_test {
namespace {

using testing::TempFolder;

std::string toy_greeting_name = "world";

int toy_simulate(const SceneFile& scene, const VerbArguments& args, std::ostream& out) {
  // The handler gets the file parsed once, and the arguments of the verb.
  out << "toy simulate: size " << scene.document["toy"]["size"].get<int>() << ", out "
      << args.out_dir_or("(none)") << "\n";
  return scene.document["toy"].value("fail", false) ? 1 : 0;
}

int toy_greet(const SceneFile& scene, const VerbArguments&, std::ostream& out) {
  out << "hello " << toy_greeting_name << " from " << scene.stem() << "\n";
  return 0;
}

// Registers the toy verb and kind once per process (the registry is global).
void register_toy() {
  static const bool registered = [] {
    register_verb({"greet", "greet scene.json [--name NAME]", "Greet the toy scene.", /*needs_scene=*/true,
                   [](CLI::App& command, VerbArguments&) {
                     command.add_option("--name", toy_greeting_name, "whom to greet")->type_name("NAME");
                   }});
    register_scene_kind(
        {"toy",
         "a \"toy\" section",
         [](const nlohmann::json& d) { return d.is_object() && d.contains("toy"); },
         {{"simulate", toy_simulate, "prints the toy's size"}, {"greet", toy_greet, "says hello"}}});
    return true;
  }();
  (void)registered;
}

struct Outcome {
  int code = -1;
  std::string out, err;
};

Outcome run(const std::vector<std::string>& arguments) {
  std::vector<const char*> argv{"tailor"};
  for (const std::string& a : arguments) argv.push_back(a.c_str());
  std::ostringstream out, err;
  Outcome outcome;
  outcome.code = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  outcome.out = out.str();
  outcome.err = err.str();
  return outcome;
}

class CliRegistry : public ::testing::Test {
 protected:
  void SetUp() override {
    register_toy();
    std::ofstream(folder_ / "toy.json") << R"({"toy": {"size": 3}})";
    std::ofstream(folder_ / "broken_toy.json") << R"({"toy": {"size": 3, "fail": true}})";
  }
  TempFolder folder_{"cli_registry"};
  std::string toy_ = folder_ / "toy.json";
};

TEST_F(CliRegistry, AKindRegisteredFromOutsideRunsItsVerbs) {
  Outcome r = run({"simulate", toy_, "--out", "somewhere"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "toy simulate: size 3, out somewhere\n");
  r = run({"simulate", folder_ / "broken_toy.json"});
  EXPECT_EQ(r.code, 1) << r.err;  // the handler's exit code

  // Its own verb with its own flag, which the other verbs do not accept.
  r = run({"greet", toy_, "--name", "Ada"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "hello Ada from toy\n");
  r = run({"simulate", toy_, "--name", "Ada"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown option '--name' for 'simulate'"), std::string::npos) << r.err;
}

TEST_F(CliRegistry, AVerbTheKindDoesNotSupportIsAUsageErrorListingItsVerbs) {
  Outcome r = run({"modes", toy_});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("'modes' does not apply to " + toy_ + ", a toy scene"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("its verbs: simulate, greet"), std::string::npos) << r.err;

  // tailor's own kinds answer the same way, and the new verb does not apply to them.
  const std::string cantilever = testing::kScenesDir + "/cantilever.json";
  r = run({"homogenize", cantilever});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("a static scene"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("its verbs: simulate, check, gradcheck, run, modes"), std::string::npos) << r.err;
  r = run({"greet", cantilever});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("'greet' does not apply"), std::string::npos) << r.err;
}

TEST_F(CliRegistry, TheUsageTextComesFromTheTable) {
  Outcome r = run({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("  greet scene.json [--name NAME]\n      Greet the toy scene."), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("toy             a \"toy\" section\n                  verbs: simulate, greet"),
            std::string::npos)
      << r.out;
  // The program's kinds are tried first: the toy is listed before tailor's own.
  EXPECT_LT(r.out.find("  toy "), r.out.find("  material_fit "));

  r = run({"greet", "--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("usage: tailor greet scene.json [--name NAME]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--name NAME"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("says hello"), std::string::npos) << r.out;
}

TEST_F(CliRegistry, BadRegistrationsAreRefused) {
  const auto handler = [](const SceneFile&, const VerbArguments&, std::ostream&) { return 0; };
  const auto recognise = [](const nlohmann::json&) { return false; };
  EXPECT_THROW(register_scene_kind({"toy", "again", recognise, {{"simulate", handler, ""}}}),
               std::logic_error);
  EXPECT_THROW(register_scene_kind({"typo", "x", recognise, {{"simulat", handler, ""}}}), std::logic_error);
  EXPECT_THROW(register_scene_kind({"nothing", "x", recognise, {}}), std::logic_error);
  EXPECT_THROW(register_scene_kind({"blind", "x", nullptr, {{"simulate", handler, ""}}}), std::logic_error);
  EXPECT_THROW(register_scene_kind({"twice", "x", recognise, {{"run", handler, ""}, {"run", handler, ""}}}),
               std::logic_error);
  EXPECT_THROW(register_verb({"run", "run", "again", true, nullptr}), std::logic_error);
  EXPECT_THROW(register_verb({"--run", "run", "a flag", true, nullptr}), std::logic_error);
  try {
    register_scene_kind({"typo", "x", recognise, {{"simulat", handler, ""}}});
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'simulat', which is not registered"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(run({"simulate", toy_}).code, 0);  // the refused ones left the table as it was
}

// Bad flag values are usage errors (exit 2) whose message names the flag; nothing runs.
TEST_F(CliRegistry, BadFlagValuesExitWithTwoNamingTheFlag) {
  const struct {
    std::vector<std::string> arguments;
    std::string message;
  } cases[] = {
      {{"modes", toy_, "--count", "0"}, "--count: expected an integer from 1 to 100000, got '0'"},
      {{"modes", toy_, "--count", "12x"}, "--count: expected an integer from 1 to 100000, got '12x'"},
      {{"check", toy_, "--seed", "-1"}, "--seed: expected an integer from 0 to 4294967295, got '-1'"},
      {{"simulate", toy_, "--threads", "zero"}, "--threads: expected an integer from 1 to 4096, got 'zero'"},
      {{"--threads", "0", "simulate", toy_}, "--threads: expected an integer from 1 to 4096, got '0'"},
      {{"simulate", "--factorization-threads", "2"},
       "--factorization-threads: expected an integer from 0 to 1"},
      {{"gradcheck", toy_, "--seed"}, "--seed"},
      {{"simulate", toy_, "--out"}, "--out"},
      {{"run", testing::kScenesDir + "/material_fit/spline_fit_neo_hookean.json", "--checkpoint-every", "3"},
       "--resume and --checkpoint-every are not implemented for material fits (only for FEM scenes with an "
       "\"inverse\" section)"},
  };
  for (const auto& c : cases) {
    const Outcome r = run(c.arguments);
    EXPECT_EQ(r.code, 2) << c.message;
    EXPECT_NE(r.err.find("tailor: " + c.message), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

// One rule for every kind's default output folder: out/<the scene's "name">, else out/<stem>.
TEST(SceneFile, DefaultOutputFolderIsTheSceneNameOrTheFileStem) {
  SceneFile file;
  file.path = "scenes/rods/rod_cantilever.json";
  file.document = nlohmann::json::object();
  EXPECT_EQ(file.default_out_dir(), "out/rod_cantilever");
  file.document["name"] = "bent";
  EXPECT_EQ(file.default_out_dir(), "out/bent");
  file.document["name"] = "";  // no name: the stem
  EXPECT_EQ(file.default_out_dir(), "out/rod_cantilever");
  file.document["name"] = 3;  // not a name (the kind's parser reports it): the stem
  EXPECT_EQ(file.default_out_dir(), "out/rod_cantilever");
  file.document = nlohmann::json(nlohmann::json::value_t::discarded);  // not JSON
  EXPECT_EQ(file.default_out_dir(), "out/rod_cantilever");
}

TEST_F(CliRegistry, HelpAndVersionExitWithZero) {
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"--help"}, {"-h"}, {"simulate", "--help"}, {"run", "-h"}, {"--version"}}) {
    const Outcome r = run(arguments);
    EXPECT_EQ(r.code, 0) << arguments[0];
    EXPECT_FALSE(r.out.empty());
    EXPECT_EQ(r.err, "");
  }
  const Outcome r = run({"run", "--help"});
  EXPECT_NE(
      r.out.find("usage: tailor run scene.json [--out DIR] [--quiet] [--checkpoint-every K] [--resume DIR]"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("material_fit"), std::string::npos) << r.out;  // the kinds that support it
  EXPECT_EQ(r.out.find("rigid_bodies"), std::string::npos) << r.out;  // and only those
  EXPECT_NE(r.out.find("--threads N"), std::string::npos) << r.out;   // with the flags of every verb
}

}  // namespace
}  // namespace tailor::cli_registry_test
