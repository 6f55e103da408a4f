// One function per subcommand of `mfdem`: each declares its options on the app and, when the
// subcommand is chosen, sets `action` to what it does (run after parsing succeeded).
#pragma once

#include <functional>
#include <ostream>

#include <CLI/CLI.hpp>

namespace mfdem::cli {

using Action = std::function<int()>;

void add_run_command(CLI::App& app, Action& action);
void add_check_command(CLI::App& app, Action& action, std::ostream& out, std::ostream& err);
void add_version_command(CLI::App& app, Action& action, std::ostream& out);
void add_shapes_command(CLI::App& app, Action& action, std::ostream& out, std::ostream& err);
void add_push_commands(CLI::App& app, Action& action);  // pack, push, push-test
void add_compare_command(CLI::App& app, Action& action);
void add_plot_command(CLI::App& app, Action& action);
void add_calibrate_command(CLI::App& app, Action& action);
void add_optimise_layer_command(CLI::App& app, Action& action);
void add_stats_command(CLI::App& app, Action& action);
void add_trade_command(CLI::App& app, Action& action);

}  // namespace mfdem::cli
