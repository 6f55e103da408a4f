#pragma once
// The processes of a campaign command's --jobs: mfdem started again with the command's own
// arguments, each computing a share of the runs into the same store (the store takes concurrent
// writers), while the first process computes its own share and then writes the tables.
#include <sys/types.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace mfdem::cli {

// mfdem (this executable) with `args`, its output into `log`; throws naming worker `number` when
// it cannot be started.
pid_t spawn_worker(const std::vector<std::string>& args, const std::filesystem::path& log, int number);

// Waits for every worker, calling `poll` about once a second meanwhile.
void wait_for_workers(const std::vector<pid_t>& workers, const std::function<void()>& poll);

// --jobs N of a command with --slice (stats, trade): the other N - 1 slices k/N (k = 1 .. N-1),
// each `args` (the command and its options, without --slice and --jobs) with --slice k/N --worker
// --quiet, logged to OUT/logs/worker-K.log. This process computes slice 0/N.
std::vector<pid_t> spawn_slice_workers(std::vector<std::string> args, int jobs, const std::filesystem::path& out);

// --jobs on a campaign command, and the hidden --worker flag its workers are started with.
void add_jobs_options(CLI::App& command, int& jobs, bool& worker);

}  // namespace mfdem::cli
