#pragma once
// A campaign command's share of the runs when several processes fill one store: the MPI rank's
// under `mpirun` (the MPI build), the `--slice K/N` of a cluster job array's task, or all of them.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include <string>

#include "studies/campaigns/run_slice.hpp"
#include "studies/cli/commands.hpp"
#include "studies/cli/process_ranks.hpp"
#include "studies/config/config_error.hpp"

namespace mfdem::cli {

struct CampaignShare {
  campaigns::RunSlice slice;
  bool mpi = false;  // the slice is this MPI rank's
  // Rank 0 (or the only process) prints progress and writes the tables.
  bool writes_tables() const { return !mpi || slice.index == 0; }
};

// Refuses --slice under mpirun (the ranks are the slices) and --jobs > 1 with either (the share
// is already one process's), naming the option.
inline CampaignShare campaign_share(const std::string& slice_option, int jobs) {
  CampaignShare share;
  const ProcessRanks ranks = process_ranks();
  if (ranks.size > 1) {
    if (!slice_option.empty())
      throw config::ConfigError(fmt::format("--slice {}: under mpirun the {} ranks share the runs themselves; "
                                            "give --slice to separate processes (a job array) only", slice_option,
                                            ranks.size));
    share.slice = {static_cast<std::size_t>(ranks.rank), static_cast<std::size_t>(ranks.size)};
    share.mpi = true;
  } else if (!slice_option.empty()) {
    share.slice = campaigns::parse_run_slice(slice_option, "--slice");
  }
  if (!share.slice.whole() && jobs > 1)
    throw config::ConfigError(fmt::format("--jobs {}: with {} a process computes its share alone (--jobs 1)", jobs,
                                          share.mpi ? "mpirun" : "--slice"));
  return share;
}

// --slice K/N on a campaign command.
inline void add_slice_option(CLI::App& command, std::string& slice) {
  command.add_option("--slice", slice,
                     "Compute only this process's share K/N of the runs (a cluster job array's task K of N, from 0); "
                     "the last slice to finish writes the table. Under mpirun the ranks share the runs themselves");
}

// After a --slice process's runs: true (and says so) while other slices' runs are still missing,
// so that only the slice that finishes last writes the tables.
inline bool other_slices_pending(const CampaignShare& share, std::size_t missing, const char* command) {
  if (share.slice.whole() || share.mpi || missing == 0) return false;
  fmt::print(stderr, "{}: slice {}/{} done; {} runs of other slices are still missing: the slice that finishes last "
                     "writes the table (or run the command again without --slice)\n",
             command, share.slice.index, share.slice.count, missing);
  return true;
}

// Campaign commands run the seeds of --seeds: a single --seed is refused.
inline void refuse_single_seed(const CommonOptions& common, const char* command) {
  if (common.seed_given)
    throw config::ConfigError(fmt::format("--seed {}: {} runs the seeds of --seeds", common.seed, command));
}

// calibrate and optimise-layer choose each run from the ones before: one process, not mpirun -np N.
inline void require_one_process(const char* command) {
  if (const ProcessRanks ranks = process_ranks(); ranks.size > 1)
    throw config::ConfigError(fmt::format("mpirun -np {}: {} chooses each run from the runs before it, so it runs as "
                                          "one process (mpirun -np 1, or without mpirun); spread compare and stats "
                                          "over ranks instead", ranks.size, command));
}

}  // namespace mfdem::cli
