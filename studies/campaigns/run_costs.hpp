#pragma once
// What a study's missing runs will cost, from the walls of the runs it has already finished: the
// progress line of a resumed study weighs each run by its model's cost (an all-clump run of the
// study preset costs about three all-ball runs) instead of counting runs alike.
#include <cstddef>
#include <vector>

#include "studies/campaigns/compare.hpp"
#include "studies/runs/run_store.hpp"

namespace mfdem::campaigns {

struct RunCosts {
  // Per run of run_keys(request): its expected wall in seconds (a model's preparation + push, the
  // median over its finished runs in the store; a model with none, the mean of the others'), plus
  // for a seed with no finished run its share of a deposition. All 1 when the store has no
  // finished run of the request: the runs are then counted.
  std::vector<double> seconds;
  bool measured = false;
  // The runs not yet in the store (indices into run_keys) and their expected seconds (the sum of
  // their `seconds`).
  std::vector<std::size_t> missing_runs;
  double missing = 0.0;
};

RunCosts expected_run_costs(const runs::RunStore& store, const CompareRequest& request);

}  // namespace mfdem::campaigns
