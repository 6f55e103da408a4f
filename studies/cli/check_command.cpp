#include <filesystem>
#include <memory>
#include <vector>

#include "studies/cli/app.hpp"
#include "studies/cli/commands.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/config/config_error.hpp"

namespace mfdem::cli {

void add_check_command(CLI::App& app, Action& action, std::ostream& out, std::ostream& err) {
  auto files = std::make_shared<std::vector<std::filesystem::path>>();
  CLI::App* check = app.add_subcommand("check", "Validate scene files without running them");
  check->footer(
      "Checks the TOML syntax, that every key is known (a typo is reported with the nearest valid\n"
      "key), and that every value has the right type and lies in its physical range. Prints\n"
      "'OK: <file>' for each valid file; the exit status is 2 if any file has an error.");
  check->add_option("files", *files, "Scene files (TOML) to check")->required();
  check->callback([files, &action, &out, &err] {
    action = [files, &out, &err] {
      int status = 0;
      for (const auto& file : *files) {
        try {
          check_scene_file(file);
          out << "OK: " << file.string() << "\n";
        } catch (const config::ConfigError& error) {
          print_error(err, error.what());
          status = 2;
        }
      }
      return status;
    };
  });
}

}  // namespace mfdem::cli
