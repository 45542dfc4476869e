// bench::Cli (bench/bench_cli.hpp) on CLI11: the one translation unit of the benches that
// compiles it.
#include "bench/bench_cli.hpp"

#include <CLI/CLI.hpp>

#include "problems/cli/flag_checks.hpp"

namespace tailor::bench {

struct Cli::Parser {
  CLI::App app;
};

namespace {

std::string joined(const std::vector<std::string>& words, const char* separator) {
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : separator) + w;
  return text;
}

}  // namespace

Cli::Cli(const std::string& program, const std::string& description)
    : program_(program), parser_(new Parser{CLI::App(description, program)}) {
  CLI::App& app = parser_->app;
  app.set_help_flag("-h,--help", "print this help and exit");
  app.allow_extras();  // reported by parse() as "unknown flag '--x'"
  app.get_formatter()->column_width(34);
}

Cli::~Cli() = default;

void Cli::out(std::string& path, const std::string& what, const std::string& type) {
  parser_->app.add_option("--out", path, what)->type_name(type)->capture_default_str();
}

void Cli::integer(const std::string& flag, int& value, const std::string& what, int min) {
  parser_->app.add_option(flag, value, what + " (>= " + std::to_string(min) + ")")
      ->type_name("N")
      ->check(cli::integer_in(min))
      ->capture_default_str();
}

void Cli::integers(const std::string& flag, std::vector<int>& values, const std::string& what, int min) {
  std::string defaults;
  for (const int v : values) defaults += (defaults.empty() ? "" : ",") + std::to_string(v);
  parser_->app.add_option(flag, values, what + " (each >= " + std::to_string(min) + ")")
      ->type_name("N[,N...]")
      ->delimiter(',')
      ->check(cli::integer_in(min))
      ->default_str(defaults);
}

void Cli::number(const std::string& flag, double& value, const std::string& what, double min,
                 bool inclusive) {
  parser_->app.add_option(flag, value, what + (inclusive ? " (>= " : " (> ") + format_number(min) + ")")
      ->type_name("X")
      ->check(cli::number_above(min, inclusive))
      ->capture_default_str();
}

void Cli::flag(const std::string& flag, bool& value, const std::string& what) {
  parser_->app.add_flag(flag, value, what);
}

void Cli::flag(const std::string& flag, std::function<void()> set, const std::string& what) {
  parser_->app.add_flag_callback(flag, std::move(set), what);
}

void Cli::on_off(const std::string& on, const std::string& off, std::function<void(bool)> set,
                 const std::string& on_what, const std::string& off_what) {
  CLI::Option* first = parser_->app.add_flag_callback(
      on, [set] { set(true); }, on_what);
  parser_->app
      .add_flag_callback(
          off, [set] { set(false); }, off_what)
      ->excludes(first);
}

void Cli::text(const std::string& flag, std::string& value, const std::string& what,
               const std::string& type) {
  parser_->app.add_option(flag, value, what)->type_name(type)->capture_default_str();
}

void Cli::choice(const std::string& flag, std::string& value, const std::string& what,
                 const std::vector<std::string>& words) {
  parser_->app.add_option(flag, value, what)
      ->type_name(joined(words, "|"))
      ->check(cli::one_of(words))
      ->capture_default_str();
}

void Cli::choices(const std::string& flag, std::vector<std::string>& values, const std::string& what,
                  const std::vector<std::string>& words) {
  parser_->app.add_option(flag, values, what)
      ->type_name(joined(words, "|") + "[,...]")
      ->delimiter(',')
      ->check(cli::one_of(words))
      ->capture_default_str();
}

void Cli::names(const std::string& flag, std::vector<std::string>& values, const std::string& what,
                const std::string& type, std::function<std::string(const std::string&)> check) {
  parser_->app.add_option(flag, values, what)
      ->type_name(type)
      ->delimiter(',')
      ->check(CLI::Validator([check](std::string& name) { return check(name); }, type));
}

std::optional<int> Cli::parse(int argc, const char* const* argv) {
  CLI::App& app = parser_->app;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    return usage_error(e.what());
  }
  const std::vector<std::string> extra = app.remaining();
  if (!extra.empty())
    return usage_error((extra[0].rfind('-', 0) == 0 ? "unknown flag '" : "unexpected argument '") + extra[0] +
                       "'");
  return std::nullopt;
}

int Cli::usage_error(const std::string& what) const {
  std::cerr << program_ << ": " << what << "\nRun '" << program_ << " --help' for its flags.\n";
  return 2;
}

}  // namespace tailor::bench
