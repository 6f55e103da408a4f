#pragma once
// A stand-in for the DEM pushes of calibrate and optimise-layer: an analytic function of
// (mu_r, the ball layer's extent) with the packing seed's scatter, its runs kept in a run store as
// DEM runs are (so a restarted study finds them). The reference (all-clump) is the function's
// reference point.
#include <fmt/format.h>

#include <functional>
#include <stdexcept>
#include <string>

#include "fidelity/policy.hpp"
#include "studies/campaigns/calibrate.hpp"

namespace mfdem::test {

struct StandInOutputs {
  double peak = 0.0, contact = 0.0;  // N
  double wall = 1.0;                 // s, preparation and push
};

// Uniform in [-1, 1], deterministic in (a, b).
inline double unit_noise(std::uint64_t a, std::uint64_t b) {
  const std::uint64_t x = (a * 6364136223846793005ULL + b * 1442695040888963407ULL) ^ (a >> 7);
  return double((x >> 11) % 2000001) / 1000000.0 - 1.0;
}

class StandInRunner final : public campaigns::CandidateRunner {
 public:
  // `model_outputs(mu_r, extent)` for a model with balls, `reference` for all-clump. A seed's
  // packing shifts every model's outputs alike (`shared_noise`, paired), each run adds its own
  // (`own_noise`). The `fail_after`-th computed run throws "killed" (the study stops there).
  StandInRunner(runs::RunStore& store, std::function<StandInOutputs(double, double)> model_outputs,
                StandInOutputs reference, double shared_noise = 0.03, double own_noise = 0.005, int fail_after = -1)
      : store_(store), model_outputs_(std::move(model_outputs)), reference_(reference), shared_noise_(shared_noise),
        own_noise_(own_noise), fail_after_(fail_after) {}
  int computed = 0;

  campaigns::RunOutputs run(const campaigns::Model& model, std::uint64_t seed, calibration::Level) override {
    const std::string key =
        runs::folder_name(fmt::format("s{}-{}-{}", seed, model.policy, model.rolling_friction.value_or(-1)));
    store_.ensure(key, "test", [&](const std::filesystem::path&) {
      if (computed == fail_after_) throw std::logic_error("killed");  // rethrown: the study stops
      ++computed;
      StandInOutputs o = reference_;
      if (model.policy != "all-clump")
        o = model_outputs_(*model.rolling_friction, fidelity::parse_policy_spec(model.policy).parameters.at(0).value);
      const double shared = 1.0 + shared_noise_ * unit_noise(seed, 1);
      const std::uint64_t own = std::hash<std::string>{}(key);
      runs::RunRecord r;
      r.numbers = {{"peak_force", o.peak * shared * (1.0 + own_noise_ * unit_noise(own, 2))},
                   {"max_contact_force", o.contact * shared * (1.0 + own_noise_ * unit_noise(own, 3))},
                   {"push_wall_seconds", o.wall}};
      return r;
    }, [](const std::exception& e) { return dynamic_cast<const std::logic_error*>(&e) != nullptr; });
    const auto record = store_.find(key);
    const double wall = *record->number("push_wall_seconds");
    return {*record->number("peak_force"), *record->number("max_contact_force"), wall, wall};
  }

 private:
  runs::RunStore& store_;
  std::function<StandInOutputs(double, double)> model_outputs_;
  StandInOutputs reference_;
  double shared_noise_, own_noise_;
  int fail_after_;
};

}  // namespace mfdem::test
