#include "studies/cli/subcommands.hpp"
#include "studies/cli/version.hpp"

namespace mfdem::cli {

void add_version_command(CLI::App& app, Action& action, std::ostream& out) {
  CLI::App* version = app.add_subcommand("version", "Print the version and how this mfdem was built");
  version->footer(
      "Prints the version, the git revision it was built from, the compiler, assertions,\n"
      "sanitizers and OpenMP threads. Quote it with any result or bug report.");
  version->callback([&action, &out] {
    action = [&out] {
      out << build_report();
      return 0;
    };
  });
}

}  // namespace mfdem::cli
