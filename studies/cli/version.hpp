// What was built: version and git revision (fixed at configure time), compiler and build flags.
#pragma once

#include <string>

namespace mfdem::cli {

std::string version();       // "0.1.0"
std::string git_revision();  // `git describe --always --dirty --tags` at configure time, or "unknown"
std::string version_line();  // "mfdem 0.1.0 (git 1a2b3c4)"
// version_line() followed by the compiler, optimisation, sanitizers and OpenMP, one per line.
std::string build_report();

}  // namespace mfdem::cli
