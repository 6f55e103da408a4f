#include <filesystem>
#include <memory>
#include <vector>

#include "studies/cli/app.hpp"
#include "studies/cli/commands.hpp"
#include "studies/cli/subcommands.hpp"
#include "studies/config/config.hpp"
#include "studies/railway/push_config.hpp"

namespace mfdem::cli {
namespace {

// A scene has a [simulation] table; a push-study config (the form of the presets) has none, and a
// preset may be named instead of a file. Returns what the file was checked as.
std::string check_file(const std::filesystem::path& file) {
  const bool preset_name = !std::filesystem::exists(file) && file.string().find('/') == std::string::npos &&
                           file.extension() != ".toml";
  if (!preset_name && config::load(file).has("simulation")) {  // load names a missing file itself
    check_scene_file(file);
    return "scene";
  }
  railway::load_push_config(file.string());
  return "push-study config";
}

}  // namespace

void add_check_command(CLI::App& app, Action& action, std::ostream& out, std::ostream& err) {
  auto files = std::make_shared<std::vector<std::filesystem::path>>();
  CLI::App* check = app.add_subcommand("check", "Validate scene files and study configs without running them");
  check->footer(
      "Checks the TOML syntax, that every key is known (a typo is reported with the nearest valid\n"
      "key), and that every value has the right type and lies in its physical range. Prints\n"
      "'OK: <file> (scene)' or '(push-study config)' for each valid file; the exit status is 2 if\n"
      "any file has an error, and every file is checked. A file with a [simulation] table is a scene\n"
      "(`mfdem run`); any other is a push-study config (`mfdem pack`, `push-test`, `compare`), whose\n"
      "section geometry is checked too. A preset's name checks the preset.");
  check->add_option("files", *files, "Scene files or study configs (TOML), or preset names")->required();
  check->callback([files, &action, &out, &err] {
    action = [files, &out, &err] {
      int status = 0;
      for (const auto& file : *files) {
        try {
          const std::string kind = check_file(file);
          out << "OK: " << file.string() << " (" << kind << ")\n";
        } catch (const std::exception& error) {  // a config error, or no such file or preset
          print_error(err, error.what());
          status = 2;
        }
      }
      return status;
    };
  });
}

}  // namespace mfdem::cli
