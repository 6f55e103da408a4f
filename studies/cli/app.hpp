// The `mfdem` command line: parses the arguments, runs the chosen subcommand, and turns every
// failure into a message and an exit status, never a crash:
//   0 success, 1 failure while running (std::exception), 2 a mistake in the command line or in a
//   config file (config::ConfigError).
#pragma once

#include <ostream>
#include <string_view>

namespace mfdem::cli {

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

// Writes `message` to `err` with every line prefixed "mfdem: error: ", the one form in which the
// command line reports problems.
void print_error(std::ostream& err, std::string_view message);

}  // namespace mfdem::cli
