#include "studies/campaigns/optimise_layer.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <stdexcept>

#include "calibration/sobol_design.hpp"

namespace mfdem::campaigns {
namespace {

double standard_error(const MeanInterval& m) { return m.standard_deviation / std::sqrt(double(m.n)); }

// The two outputs a calibration matches, as the surrogate takes them.
Eigen::VectorXd matched(const RunOutputs& r) { return Eigen::Vector2d(r.peak_force, r.contact_force); }

class LayerSearch {
 public:
  LayerSearch(CandidateRunner& runner, const OptimiseLayerRequest& request, OptimiseLayerResult& result)
      : runner_(runner), request_(request), result_(result),
        bounds_{{request.friction.lower, request.friction.upper}, {request.extent.lower, request.extent.upper}},
        targets_{calibration::relative_target(result.targets[0]), calibration::relative_target(result.targets[1])} {
    search_.shortest_length = request.shortest_length;
  }

  // Runs (mu_r, extent) on every seed, once.
  const std::vector<RunOutputs>& run(double mu_r, double extent) {
    const auto key = std::pair{mu_r, extent};
    if (auto found = per_point_.find(key); found != per_point_.end()) return found->second;
    Eigen::VectorXd x(2);
    x << mu_r, extent;
    const Model model = candidate_model(request_.policy, {request_.friction, request_.extent}, x);
    std::vector<RunOutputs> per_seed;
    for (auto seed : request_.seeds) {
      per_seed.push_back(runner_.run(model, seed, calibration::Level::expensive));
      result_.candidates_wall += per_seed.back().wall;
      ++result_.dem_runs;
    }
    result_.runs.push_back({x, calibration::Level::expensive, matched(mean_outputs(per_seed))});
    return per_point_.emplace(key, std::move(per_seed)).first->second;
  }

  // mu_r calibrated at one extent: the minimiser of the predicted misfit there, run, until it
  // lands within 2 % of the range of a run already made at this extent.
  LayerCandidate calibrate_at(double extent) {
    int runs_here = 0;
    for (int k = 0; k < request_.runs_per_extent; ++k) {
      const double mu_r = predicted_best_friction(extent);
      bool settled = false;
      for (const auto& [point, outputs] : per_point_)
        settled |= point.second == extent &&
                   std::abs(point.first - mu_r) <= 0.02 * (request_.friction.upper - request_.friction.lower);
      if (settled) break;
      run(mu_r, extent);
      ++runs_here;
    }
    // The best run at this extent, by its measured misfit.
    auto best = per_point_.end();
    double best_misfit = INFINITY;
    for (auto it = per_point_.begin(); it != per_point_.end(); ++it) {
      if (it->first.second != extent) continue;
      const double m = calibration::misfit(matched(mean_outputs(it->second)), targets_);
      if (m < best_misfit) best_misfit = m, best = it;
    }
    if (best == per_point_.end()) throw std::logic_error("optimise_layer: no run at a calibrated extent");
    LayerCandidate c = measure_candidate(best->second, result_.reference_runs, request_.tolerance);
    c.extent = extent;
    c.rolling_friction = best->first.first;
    c.runs_here = runs_here;
    return c;
  }

 private:
  // On a fine grid of mu_r at the extent: the surrogate is smooth and one-dimensional here.
  double predicted_best_friction(double extent) {
    calibration::MisfitSurrogate surrogate(bounds_, targets_, calibration::KernelKind::matern52, search_);
    surrogate.fit(result_.runs);
    double best = request_.friction.lower, best_misfit = INFINITY;
    constexpr int kSteps = 240;
    for (int k = 0; k <= kSteps; ++k) {
      Eigen::VectorXd x(2);
      x << request_.friction.lower + (request_.friction.upper - request_.friction.lower) * k / kSteps, extent;
      const double m = surrogate.predict(x).mean;
      if (m < best_misfit) best_misfit = m, best = x(0);
    }
    return best;
  }

  CandidateRunner& runner_;
  const OptimiseLayerRequest& request_;
  OptimiseLayerResult& result_;
  std::vector<calibration::Bounds> bounds_;
  std::vector<calibration::Target> targets_;
  calibration::HyperparameterSearch search_;
  std::map<std::pair<double, double>, std::vector<RunOutputs>> per_point_;
};

}  // namespace

LayerCandidate measure_candidate(const std::vector<RunOutputs>& per_seed, const std::vector<RunOutputs>& reference,
                                 double tolerance) {
  if (per_seed.size() != reference.size() || per_seed.empty())
    throw std::invalid_argument("measure_candidate: the model's and the reference's runs on the same seeds");
  LayerCandidate c;
  std::vector<double> peak, contact, peak_reference, contact_reference;
  for (std::size_t s = 0; s < per_seed.size(); ++s) {
    peak.push_back(per_seed[s].peak_force), contact.push_back(per_seed[s].contact_force);
    peak_reference.push_back(reference[s].peak_force), contact_reference.push_back(reference[s].contact_force);
  }
  c.mean = mean_outputs(per_seed);
  const RunOutputs reference_mean = mean_outputs(reference);
  c.peak_error = mean_interval(relative_differences(peak, peak_reference));
  c.contact_error = mean_interval(relative_differences(contact, contact_reference));
  c.speedup = c.mean.wall > 0.0 ? reference_mean.wall / c.mean.wall : 0.0;
  c.push_speedup = c.mean.push_wall > 0.0 ? reference_mean.push_wall / c.mean.push_wall : 0.0;
  c.tolerance_used =
      std::max(tolerance, 2.0 * std::max(standard_error(c.peak_error), standard_error(c.contact_error)));
  c.within = std::abs(c.peak_error.mean) <= c.tolerance_used && std::abs(c.contact_error.mean) <= c.tolerance_used;
  return c;
}

OptimiseLayerResult optimise_layer(CandidateRunner& runner, const OptimiseLayerRequest& request) {
  if (request.seeds.size() < 2)
    throw std::invalid_argument("optimise_layer: at least two seeds (the tolerance is judged against their spread)");
  if (!(request.extent.upper > request.extent.lower) || !(request.friction.upper > request.friction.lower))
    throw std::invalid_argument("optimise_layer: empty range");
  OptimiseLayerResult result;
  result.cheaper_when_larger = request.extent.name != "d";
  for (auto seed : request.seeds)
    result.reference_runs.push_back(runner.run(request.reference_model, seed, calibration::Level::expensive));
  const RunOutputs reference = mean_outputs(result.reference_runs);
  result.targets = {reference.peak_force, reference.contact_force};
  result.reference_wall = reference.wall;
  LayerSearch search(runner, request, result);
  // The shared design over (mu_r, extent): what every extent's calibration starts from.
  for (const auto& p : calibration::sobol_design({{request.friction.lower, request.friction.upper},
                                                  {request.extent.lower, request.extent.upper}},
                                                 request.initial, std::uint64_t{1}))
    search.run(p[0], p[1]);

  const double cheapest = result.cheaper_when_larger ? request.extent.upper : request.extent.lower;
  const double dearest = result.cheaper_when_larger ? request.extent.lower : request.extent.upper;
  const auto evaluate = [&](double extent) {
    result.front.push_back(search.calibrate_at(extent));
    return result.front.back().within;
  };
  if (!evaluate(cheapest) && evaluate(dearest)) {
    // Bisection between the last extent within tolerance and the first outside it.
    double good = dearest, bad = cheapest;
    while (int(result.front.size()) < request.max_extents &&
           std::abs(bad - good) > request.resolution * (request.extent.upper - request.extent.lower)) {
      const double middle = 0.5 * (good + bad);
      (evaluate(middle) ? good : bad) = middle;
    }
  }

  // The cheapest candidate within tolerance, by measured speedup (noise may break the order of
  // the bisection).
  for (std::size_t k = 0; k < result.front.size(); ++k)
    if (result.front[k].within && (!result.chosen || result.front[k].speedup > result.front[*result.chosen].speedup))
      result.chosen = k;
  double largest_sd = 0.0;
  for (const auto& c : result.front) {
    result.resolvable_tolerance = std::max(
        result.resolvable_tolerance, 2.0 * std::max(standard_error(c.peak_error), standard_error(c.contact_error)));
    largest_sd = std::max({largest_sd, c.peak_error.standard_deviation, c.contact_error.standard_deviation});
  }
  // 2 sd / sqrt(K) <= tolerance.
  result.seeds_to_resolve = int(std::ceil(std::pow(2.0 * largest_sd / request.tolerance, 2)));
  return result;
}

}  // namespace mfdem::campaigns
