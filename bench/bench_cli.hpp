#pragma once
// The command line and the JSON report of every program in bench/, so that they agree:
//  - flags by CLI11 with --help; a bad value exits with 2 and a message naming the flag;
//  - one spelling per meaning: --tets (target tet counts, "58000" or "6000,47000"), --steps,
//    --repeats, --time-step, --max-iterations, --out FILE, --plot FILE; lists are comma-
//    separated; booleans are bare flags (--quick, --reuse-factorization);
//  - the report starts with tailor's report header (problems/report_header.hpp: version, report
//    format, threads) and "benchmark"; it is written by nlohmann::json, so strings are escaped
//    and non-finite numbers are written as null.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "forward/core/format_number.hpp"
#include "problems/cli/flag_checks.hpp"
#include "problems/json_text.hpp"
#include "problems/report_header.hpp"

namespace tailor::bench {

using Json = nlohmann::ordered_json;

class Cli {
 public:
  Cli(const std::string& program, const std::string& description)
      : program_(program), app_(description, program) {
    app_.set_help_flag("-h,--help", "print this help and exit");
    app_.allow_extras();  // reported by parse() as "unknown flag '--x'"
    app_.get_formatter()->column_width(34);
  }

  CLI::App& app() { return app_; }

  // --out FILE: the JSON report.
  CLI::Option* out(std::string& path, const std::string& what = "JSON report") {
    return app_.add_option("--out", path, what)->type_name("FILE")->capture_default_str();
  }
  // --tets: the target tet count(s) of the meshes (the mesh closest to each is used).
  CLI::Option* tets(int& count, int min = 6) {
    return integer("--tets", count, "target tet count of the mesh", min);
  }
  CLI::Option* tets(std::vector<int>& counts, int min = 6) {
    return integers("--tets", counts, "target tet counts of the meshes", min);
  }
  CLI::Option* steps(int& count, const std::string& what = "time steps") {
    return integer("--steps", count, what, 1);
  }
  CLI::Option* repeats(int& count) {
    return integer("--repeats", count, "timed repeats (the median is reported)", 1);
  }
  CLI::Option* time_step(double& h) {
    return app_.add_option("--time-step", h, "time step h")
        ->type_name("H")
        ->check(cli::number_above(0.0))
        ->capture_default_str();
  }

  // A whole number >= min.
  CLI::Option* integer(const std::string& flag, int& value, const std::string& what, int min) {
    return app_.add_option(flag, value, what + " (>= " + std::to_string(min) + ")")
        ->type_name("N")
        ->check(cli::integer_in(min))
        ->capture_default_str();
  }
  // A comma-separated list of whole numbers >= min ("6000,47000"); replaces the default list.
  CLI::Option* integers(const std::string& flag, std::vector<int>& values, const std::string& what, int min) {
    std::string defaults;
    for (const int v : values) defaults += (defaults.empty() ? "" : ",") + std::to_string(v);
    return app_.add_option(flag, values, what + " (each >= " + std::to_string(min) + ")")
        ->type_name("N[,N...]")
        ->delimiter(',')
        ->check(cli::integer_in(min))
        ->default_str(defaults);
  }
  // A finite number > min (>= min when inclusive).
  CLI::Option* number(const std::string& flag, double& value, const std::string& what, double min,
                      bool inclusive = false) {
    return app_.add_option(flag, value, what + (inclusive ? " (>= " : " (> ") + format_number(min) + ")")
        ->type_name("X")
        ->check(cli::number_above(min, inclusive))
        ->capture_default_str();
  }
  CLI::Option* flag(const std::string& flag, bool& value, const std::string& what) {
    return app_.add_flag(flag, value, what);
  }

  // Parses the command line. Returns the exit code when the program should stop: 0 after
  // --help, 2 after a bad flag or value (with the message on stderr); nullopt to go on.
  std::optional<int> parse(int argc, const char* const* argv) {
    try {
      app_.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
      std::cout << app_.help();
      return 0;
    } catch (const CLI::ParseError& e) {
      return usage_error(e.what());
    }
    const std::vector<std::string> extra = app_.remaining();
    if (!extra.empty())
      return usage_error((extra[0].rfind('-', 0) == 0 ? "unknown flag '" : "unexpected argument '") +
                         extra[0] + "'");
    return std::nullopt;
  }

  // A usage error found after parsing (e.g. flags that contradict each other): exit code 2.
  int usage_error(const std::string& what) const {
    std::cerr << program_ << ": " << what << "\nRun '" << program_ << " --help' for its flags.\n";
    return 2;
  }

 private:
  std::string program_;
  CLI::App app_;
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
