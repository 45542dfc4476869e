#pragma once
// The command line and the JSON report of every program in bench/, so that they agree:
//  - flags by CLI11 with --help; a bad value exits with 2 and a message naming the flag;
//  - one spelling per meaning: --tets (target tet counts, "58000" or "6000,47000"), --steps,
//    --repeats, --time-step, --max-iterations, --out FILE, --plot FILE; lists are comma-
//    separated; booleans are bare flags (--quick, --reuse-factorization);
//  - the report starts with tailor's report header (problems/report_header.hpp: version, report
//    format, threads) and "benchmark"; it is written by nlohmann::json, so strings are escaped
//    and non-finite numbers are written as null.
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "forward/core/format_number.hpp"
#include "problems/json_text.hpp"
#include "problems/report_header.hpp"

namespace tailor::bench {

using Json = nlohmann::ordered_json;

// The flags of one program. CLI11 stays inside bench/bench_cli.cpp: it costs every translation
// unit that includes it about 7 s of compile time (docs/testing.md, "Build time").
class Cli {
 public:
  Cli(const std::string& program, const std::string& description);
  ~Cli();
  Cli(const Cli&) = delete;
  Cli& operator=(const Cli&) = delete;

  // --out FILE: the JSON report (or another output; `type` is its placeholder in the help).
  void out(std::string& path, const std::string& what = "JSON report", const std::string& type = "FILE");
  // --tets: the target tet count(s) of the meshes (the mesh closest to each is used).
  void tets(int& count, int min = 6) { integer("--tets", count, "target tet count of the mesh", min); }
  void tets(std::vector<int>& counts, int min = 6) {
    integers("--tets", counts, "target tet counts of the meshes", min);
  }
  void steps(int& count, const std::string& what = "time steps") { integer("--steps", count, what, 1); }
  void repeats(int& count) { integer("--repeats", count, "timed repeats (the median is reported)", 1); }
  void time_step(double& h) { number("--time-step", h, "time step h", 0.0); }

  // A whole number >= min.
  void integer(const std::string& flag, int& value, const std::string& what, int min);
  // A comma-separated list of whole numbers >= min ("6000,47000"); replaces the default list.
  void integers(const std::string& flag, std::vector<int>& values, const std::string& what, int min);
  // A finite number > min (>= min when inclusive).
  void number(const std::string& flag, double& value, const std::string& what, double min,
              bool inclusive = false);
  // A bare flag.
  void flag(const std::string& flag, bool& value, const std::string& what);
  // A bare flag that runs `set` when given.
  void flag(const std::string& flag, std::function<void()> set, const std::string& what);
  // Two bare flags that exclude each other, e.g. --reuse-factorization / --no-reuse-factorization.
  void on_off(const std::string& on, const std::string& off, std::function<void(bool)> set,
              const std::string& on_what, const std::string& off_what);
  // Any text (`type` is its placeholder in the help: FILE, DIR).
  void text(const std::string& flag, std::string& value, const std::string& what, const std::string& type);
  // One of `words`.
  void choice(const std::string& flag, std::string& value, const std::string& what,
              const std::vector<std::string>& words);
  // A comma-separated list of `words`.
  void choices(const std::string& flag, std::vector<std::string>& values, const std::string& what,
               const std::vector<std::string>& words);
  // A comma-separated list of names, each accepted when `check` returns an empty string (else
  // the reason); `type` is the placeholder in the help.
  void names(const std::string& flag, std::vector<std::string>& values, const std::string& what,
             const std::string& type, std::function<std::string(const std::string&)> check);

  // Parses the command line. Returns the exit code when the program should stop: 0 after
  // --help, 2 after a bad flag or value (with the message on stderr); nullopt to go on.
  std::optional<int> parse(int argc, const char* const* argv);

  // A usage error found after parsing (e.g. flags that contradict each other): exit code 2.
  int usage_error(const std::string& what) const;

 private:
  struct Parser;  // CLI11's App
  std::string program_;
  std::unique_ptr<Parser> parser_;
};

// A report's first fields: tailor's report header, then "benchmark".
inline Json report(const std::string& benchmark) {
  Json json;
  add_report_header(json);
  json["benchmark"] = benchmark;
  return json;
}

// Writes the report (2-space indented) and says so on stdout; false, with the reason on
// stderr, when the file cannot be written. Invalid UTF-8 in strings is replaced, not thrown.
inline bool write_report(const std::string& path, const Json& json, const std::string& program) {
  std::ofstream file(path);
  file << dump_json(json, 2, true) << "\n";
  file.close();
  if (!file) {
    std::cerr << program << ": cannot write '" << path << "'\n";
    return false;
  }
  std::printf("wrote %s\n", path.c_str());
  return true;
}

// A list as a JSON array.
template <class T>
Json array(const std::vector<T>& values) {
  Json a = Json::array();
  for (const T& v : values) a.push_back(v);
  return a;
}

}  // namespace tailor::bench
