#pragma once
// A share of a campaign's runs, for one of several processes filling one run store: the MPI ranks
// of `mpirun -np N mfdem ...`, or the tasks of a cluster's job array (`--slice K/N`). The runs are
// dealt round-robin over the campaign's list (seed by seed, the models of a seed in their order),
// so each process holds about the same number of every model's runs. The store needs no lock for
// this (studies/runs/run_store.hpp); the slices only keep the processes from computing the same
// run twice.
#include <cstddef>
#include <string>

namespace mfdem::campaigns {

struct RunSlice {
  std::size_t index = 0, count = 1;  // this process is `index` of `count`
  bool holds(std::size_t run) const { return run % count == index; }
  bool whole() const { return count == 1; }
};

// "K/N" with 0 <= K < N (K counted from 0, as $SLURM_ARRAY_TASK_ID with --array=0-(N-1));
// throws config::ConfigError naming `option` and the value otherwise.
RunSlice parse_run_slice(const std::string& text, const std::string& option);

}  // namespace mfdem::campaigns
