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

#include "studies/campaigns/run_slice.hpp"
#include "studies/runs/run_store.hpp"

namespace mfdem::cli {

// mfdem (this executable, or `executable`) with `args`, its output into `log`; throws naming worker
// `number` when it cannot be started. The worker is sent SIGTERM when this process ends, however
// it ends, so no worker computes on unseen after its study was stopped.
pid_t spawn_worker(const std::vector<std::string>& args, const std::filesystem::path& log, int number,
                   const char* executable = "/proc/self/exe");

// Waits for every worker, calling `poll` about once a second meanwhile.
void wait_for_workers(const std::vector<pid_t>& workers, const std::function<void()>& poll);

// --jobs N of a command with --slice (stats, trade): `run(slice)` computes a slice of the
// campaign's runs into the store at `out`. With N > 1, the other N - 1 slices k/N run in workers,
// each `args` (the command and its options, without --slice and --jobs) with --slice k/N --worker
// --quiet, logged to OUT/logs/worker-K.log; this process runs slice 0/N, waits for them (`poll`
// about once a second), then runs the whole campaign, which finds every run (and computes one a
// worker left). With N = 1, `run(own)`: the process's own share (--slice, an MPI rank, or all).
void run_with_jobs(int jobs, const std::vector<std::string>& args, const std::filesystem::path& out,
                   const campaigns::RunSlice& own, const std::function<void(const campaigns::RunSlice&)>& run,
                   const std::function<void()>& poll);

// The detail of a campaign's progress line: `counted` ("3 of 8 runs in the store") and what the
// runs being computed in the store do ("; running: s1-all-clump settle 34 %").
std::string campaign_progress_detail(const runs::RunStore& store, const std::string& counted);

// --jobs on a campaign command, and the hidden --worker flag its workers are started with.
void add_jobs_options(CLI::App& command, int& jobs, bool& worker);

}  // namespace mfdem::cli
