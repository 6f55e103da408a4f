#include "studies/campaigns/run_costs.hpp"

#include <gsl/gsl_statistics_double.h>

#include <optional>

namespace mfdem::campaigns {
namespace {

double median_of(std::vector<double> v) { return gsl_stats_median(v.data(), 1, v.size()); }  // reorders its copy

}  // namespace

RunCosts expected_run_costs(const runs::RunStore& store, const CompareRequest& request) {
  const std::vector<std::string> keys = run_keys(request);
  const std::size_t models = request.models.size(), seeds = request.seeds.size();
  std::vector<std::vector<double>> walls(models);  // finished runs' walls, per model
  std::vector<double> depositions;
  std::vector<bool> seed_started(seeds, false), published(keys.size(), false);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    published[k] = store.has(keys[k]);
    if (!published[k]) continue;
    seed_started[k / models] = true;  // its deposition exists
    const auto record = store.find(keys[k]);
    if (!record || !record->finished()) continue;
    const auto preparation = record->number(number::kPreparationWall), push = record->number(number::kPushWall);
    if (preparation && push) walls[k % models].push_back(*preparation + *push);
    if (const auto d = record->number(number::kDepositionWall)) depositions.push_back(*d);
  }
  std::vector<std::optional<double>> per_model(models);
  double sum = 0.0;
  int known = 0;
  for (std::size_t m = 0; m < models; ++m)
    if (!walls[m].empty()) {
      per_model[m] = median_of(walls[m]);
      sum += *per_model[m];
      ++known;
    }
  RunCosts costs;
  costs.seconds.assign(keys.size(), 1.0);
  costs.measured = known > 0;
  if (costs.measured) {
    const double deposition_share = depositions.empty() ? 0.0 : median_of(depositions) / double(models);
    for (std::size_t k = 0; k < keys.size(); ++k)
      costs.seconds[k] = per_model[k % models].value_or(sum / known) + (seed_started[k / models] ? 0.0 : deposition_share);
  }
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (!published[k]) costs.missing_runs.push_back(k), costs.missing += costs.seconds[k];
  return costs;
}

}  // namespace mfdem::campaigns
