#include "studies/cli/app.hpp"

#include <algorithm>
#include <exception>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "studies/cli/subcommands.hpp"
#include "studies/cli/version.hpp"
#include "studies/config/config_error.hpp"
#include "studies/config/nearest.hpp"

namespace mfdem::cli {

namespace {

constexpr int usage_or_config_error = 2;
constexpr int run_failure = 1;

constexpr const char* description =
    "mfdem: multi-fidelity discrete element (DEM) studies of railway ballast.\n"
    "Clumps where accuracy matters, single balls with rolling resistance where it does not;\n"
    "every study reports the time and elements it saved against the accuracy it lost.";

// CLI11 would report `mfdem frobnicate` as "a subcommand is required"; name the word instead. The
// top level takes only flags without values, so after them the next word must be a subcommand;
// anything else starting with '-' is left to CLI11 to report.
std::optional<std::string> unknown_command(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> known;
  for (const CLI::App* command : app.get_subcommands({})) known.push_back(command->get_name());
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "-h" || word == "--help" || word == "--version") continue;
    if (word.empty() || word[0] == '-') return std::nullopt;
    if (std::find(known.begin(), known.end(), word) != known.end()) return std::nullopt;
    const auto suggestion = config::nearest(word, known);
    return fmt::format("unknown command '{}'; {}", word,
                       suggestion ? fmt::format("did you mean '{}'?", *suggestion)
                                  : fmt::format("the commands are: {}", fmt::join(known, ", ")));
  }
  return std::nullopt;
}

int usage_error(std::ostream& err, std::string_view message) {
  print_error(err, message);
  err << "Run 'mfdem --help' for usage.\n";
  return usage_or_config_error;
}

}  // namespace

void print_error(std::ostream& err, std::string_view message) {
  std::istringstream lines{std::string(message)};
  for (std::string line; std::getline(lines, line);) err << "mfdem: error: " << line << "\n";
}

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    CLI::App app{description, "mfdem"};
    app.set_version_flag("--version", version_line(), "Print the version and git revision, then exit");
    app.require_subcommand(1);
    app.footer("Run 'mfdem <command> --help' for the options of a command.");
    Action action;
    add_run_command(app, action);
    add_check_command(app, action, out, err);
    add_version_command(app, action, out);
    add_shapes_command(app, action, out, err);
    add_push_commands(app, action);
    add_compare_command(app, action);
    add_plot_command(app, action);
    add_calibrate_command(app, action);
    add_optimise_layer_command(app, action);
    add_stats_command(app, action);
    add_trade_command(app, action);
    if (auto message = unknown_command(app, argc, argv)) return usage_error(err, *message);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
      if (error.get_exit_code() == 0) return app.exit(error, out, err);  // --help, --version
      return usage_error(err, error.what());
    }
    return action();
  } catch (const config::ConfigError& error) {
    print_error(err, error.what());
    return usage_or_config_error;
  } catch (const std::exception& error) {
    print_error(err, error.what());
    return run_failure;
  } catch (...) {
    print_error(err, "unexpected failure (not a standard exception)");
    return run_failure;
  }
}

}  // namespace mfdem::cli
