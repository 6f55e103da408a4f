#pragma once
// Runs one stage of bed preparation until the bed is in equilibrium, or a time limit. In
// equilibrium at two consecutive checks: the mean unbalanced force ratio
// (dem::Simulation::unbalanced_force_ratio, PFC's criterion) is below the target, and so is the
// kinetic energy over `energy_scale` (the stones' weight times their mean size: the work of
// lifting the bed by one stone). The second condition stops a false "settled" while stones
// still fall: during impacts the contact forces are large and the ratio small. A stage that only
// has to land the stones (the deposition) asks for the kinetic condition alone. Checks fall on
// fixed step counts, so a stage ends on the same step whatever the thread count.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dem/simulation.hpp"
#include "dem/state_file.hpp"

namespace mfdem::railway {

struct StageReport {
  std::string name;
  double simulated_time = 0.0;     // s
  std::int64_t steps = 0;
  double unbalanced_force_ratio = 0.0;
  bool settled = false;            // false: stopped by the time limit
  double wall_seconds = 0.0;
  // m: height of the sleeper's bottom face at the stage's end (none before the sleeper is in).
  // Shows what a stage did to it: sank it, lifted it, or (held) kept it at its height.
  std::optional<double> sleeper_base;
  std::optional<double> sleeper_base_start;  // m, the sleeper's base height as the stage began
  // At every check: simulated time since the stage began (s), the unbalanced force ratio and the
  // kinetic energy over the energy scale. How the bed came to rest, or did not.
  std::vector<double> check_time, check_force_ratio, check_kinetic_ratio;
  // m: the sleeper's base height at every check (empty before the sleeper is in): how it sank or
  // rose, e.g. its settlement under each traffic pulse.
  std::vector<double> check_sleeper_base;
};

// `check_interval` in simulated seconds. With `frames`, writes the state every `frame_interval`
// simulated seconds and at the end (for a look at the preparation in ParaView).
// kFixedTime runs the whole max_time (a stage with a set duration, not a rest goal) and counts
// as settled at its end. `drive`, when given, is called before every step with the stage's
// simulated time (to move or resize a boundary).
enum class RestCriterion { kForcesAndEnergy, kEnergyOnly, kFixedTime };
using StageDrive = std::function<void(dem::Simulation&, double)>;

StageReport run_until_settled(dem::Simulation& sim, const std::string& name, double ratio_target,
                              double energy_scale, double max_time, bool quiet, RestCriterion criterion,
                              dem::StateFile* frames = nullptr,
                              double frame_interval = 0.02, double check_interval = 2e-3,
                              const StageDrive& drive = {});

}  // namespace mfdem::railway
