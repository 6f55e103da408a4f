// The options every simulating subcommand takes: --threads, --seed, --out, --quiet.
#pragma once

#include <CLI/CLI.hpp>

#include "studies/cli/commands.hpp"

namespace mfdem::cli {

// Declares the options on `command`, writing into `options` when it is parsed.
void add_common_options(CLI::App& command, CommonOptions& options);

// A command-line number that must be finite and > 0 (nan, inf, 0 and negatives refused with the
// value and what was expected, in `unit`).
CLI::Validator finite_positive(const std::string& unit);

// Sets the OpenMP thread count from --threads (0 = all cores, overriding OMP_NUM_THREADS).
void apply_thread_count(const CommonOptions& options);

}  // namespace mfdem::cli
