#pragma once
// Runs one stage of bed preparation until the bed is in equilibrium, or a time limit. In
// equilibrium at two consecutive checks: the mean unbalanced force ratio
// (dem::Simulation::unbalanced_force_ratio, PFC's criterion) is below the target, and so is the
// kinetic energy over `energy_scale` (the stones' weight times their mean size: the work of
// lifting the bed by one stone). The second condition stops a false "settled" while stones
// still fall: during impacts the contact forces are large and the ratio small. A stage that only
// has to land the stones (the deposition) asks for the kinetic condition alone. Checks fall on
// fixed step counts, so a stage ends on the same step whatever the thread count.
//
// A second way to rest (CreepGoal, off by default): the kinetic condition holds and the stones'
// mean displacement over the last window of time, over their mean size, is below a target. A bed
// whose stones have stopped moving is at rest even when its force ratio, kept up by the vibration
// of stiff contacts, hovers above the target (the study bed's ball layers stay at 1.5-3e-3 for
// 0.5 s while the sleeper creeps under a micrometre per 0.05 s), and the ratio's first dip below
// the target is a matter of luck in a noisy signal.
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
  bool settled_by_creep = false;   // true: the creep goal ended it, not the force ratio
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
  // At every check: the stones' mean displacement over the creep window (or since the first
  // check, while shorter) over their mean size; empty without a creep goal.
  std::vector<double> check_creep;
};

struct CreepGoal {
  double ratio = 0.0;         // mean displacement / length_scale over `window`; 0: not used
  double window = 0.05;       // s
  double length_scale = 0.0;  // m, the stones' mean size
  bool active() const { return ratio > 0.0; }
};

// `check_interval` in simulated seconds. With `frames`, writes the state every `frame_interval`
// simulated seconds and at the end (for a look at the preparation in ParaView).
// kFixedTime runs the whole max_time (a stage with a set duration, not a rest goal) and counts
// as settled at its end. `drive`, when given, is called before every step with the stage's
// simulated time (to move or resize a boundary). `creep` applies with kForcesAndEnergy only.
enum class RestCriterion { kForcesAndEnergy, kEnergyOnly, kFixedTime };
using StageDrive = std::function<void(dem::Simulation&, double)>;

StageReport run_until_settled(dem::Simulation& sim, const std::string& name, double ratio_target,
                              double energy_scale, double max_time, bool quiet, RestCriterion criterion,
                              dem::StateFile* frames = nullptr,
                              double frame_interval = 0.02, double check_interval = 2e-3,
                              const StageDrive& drive = {}, const CreepGoal& creep = {});

}  // namespace mfdem::railway
