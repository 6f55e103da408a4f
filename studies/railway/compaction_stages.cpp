#include "studies/railway/compaction_stages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "studies/railway/packing.hpp"

namespace mfdem::railway {

// Step 4b, radius expansion: grows the stones back to their drawn size in equal factors, the
// bed moving for an equal time after each (each a solver run of its own: radii are fixed within
// a run; contact springs restart and reload within micrometres of slip), the sleeper's tamping
// cut (the sleeper itself without tamping) in place.
StageReport run_expansion(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
                          BedBetweenStages& bed) {
  StageSetup grow = settle;
  grow.sleeper = inset(*settle.sleeper, c.preparation.tamping_depth);
  const int steps = c.preparation.expansion_steps;
  const double factor = std::pow(1.0 + c.preparation.expansion_strain, 1.0 / steps);
  StageReport total;
  total.name = "expand";
  for (int k = 0; k < steps; ++k) {
    for (auto& s : bed.stones) s = scaled(s, factor);
    const Stage step = run_stage(c, bed.domain, bed.stones, grow, {"expand", c.preparation.equilibrium_ratio,
                                 c.preparation.expansion_time / steps, bed.mean_size, RestCriterion::kFixedTime},
                                 true, {});
    bed.stones = body_states(step.sim);
    grow.sleeper->centre = step.sim.boxes()[0].centre;
    total.simulated_time += step.report.simulated_time;
    total.steps += step.report.steps;
    total.wall_seconds += step.report.wall_seconds;
    total.unbalanced_force_ratio = step.report.unbalanced_force_ratio;
    total.sleeper_base = step.report.sleeper_base;
    if (k == 0) total.sleeper_base_start = step.report.sleeper_base_start;
    if (!control.quiet)
      fmt::print(stderr, "expand: step {}/{}, sleeper base at z = {:.4f} m, unbalanced force ratio {:.2e}\n", k + 1,
                 steps, *total.sleeper_base, total.unbalanced_force_ratio);
  }
  bed.sleeper_centre = grow.sleeper->centre;
  total.settled = true;  // a set duration
  return total;
}

// Step 5: tamping. The sleeper grows from the cut to its size: its sides and ends press the
// stones beside them into the cribs and shoulders by up to tamping_depth. Without it the sleeper
// stands in a hole up to a stone's size too large and the crib stones lean loosely on its sides
// (standard seed 1: 201 stones touch it untamped, 310 tamped 5 mm).
StageReport run_tamping(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
                        BedBetweenStages& bed) {
  const dem::RigidBox full = *settle.sleeper;
  const double depth = c.preparation.tamping_depth;
  StageSetup setup = settle;
  setup.sleeper = inset(full, depth);
  // Free vertically by default: it sinks onto the stones under it while the cribs are packed.
  // Held (tamping_sleeper_vertical), it can squeeze deeper without being pressed out upwards,
  // and the cribs then carry part of its weight (mini, 10 mm: the crib sides carried 84 %).
  setup.sleeper->driven = {true, true, c.preparation.tamping_sleeper_held};
  const double duration = c.preparation.tamping_time;
  // Grows at a steady rate and stops at the full size (within round-off of tamping_depth).
  const StageDrive grow = [&](dem::Simulation& sim, double) {
    dem::RigidBox& box = sim.mutable_boxes()[0];
    const double remaining = full.half_extent.x() - box.half_extent.x();
    const double rate = std::min(depth / duration, remaining / sim.time_step());
    box.growth_rate = std::max(0.0, rate) * kTampedAxes;
  };
  const Stage tamping = run_stage(c, bed.domain, bed.stones, setup, {"tamp", c.preparation.equilibrium_ratio,
                                  duration, bed.mean_size, RestCriterion::kFixedTime}, control.quiet,
                                  control.stage_directory, grow);
  bed.stones = body_states(tamping.sim);
  bed.sleeper_centre = tamping.sim.boxes()[0].centre;  // where it sank to
  return tamping.report;
}

// Step 5b: consolidation. Everything weighs consolidation_gravity times more for a while: the
// bed compacts under the heavier sleeper and its own weight, and, settled again at 1 g, keeps
// part of the lateral stress (an overconsolidated soil's K exceeds K0). Without it the stones
// beside the cut lean on the sleeper with K about 0.1 (standard seed 1, results/push_test).
StageReport run_consolidation(const PushStudyConfig& c, const StageSetup& settle,
                              const PreparationControl& control, BedBetweenStages& bed) {
  StageSetup heavy = settle;
  heavy.gravity_factor = c.preparation.consolidation_gravity;
  const Stage consolidation = run_stage(c, bed.domain, bed.stones, heavy,
                                        {"consolidate", c.preparation.equilibrium_ratio,
                                         c.preparation.consolidation_time, bed.mean_size, RestCriterion::kFixedTime},
                                        control.quiet, control.stage_directory);
  bed.stones = body_states(consolidation.sim);
  bed.sleeper_centre = consolidation.sim.boxes()[0].centre;
  return consolidation.report;
}

// Step 5c: traffic. The sleeper, held across and along the track as by its rails and free
// vertically, takes traffic_cycles load pulses P sin^2(pi t / T): the bed under it compacts as
// under passing axles, and the sleeper sinks a little more with each (printed per cycle: the
// settlement curve of a ballast box test).
StageReport run_traffic(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
                        BedBetweenStages& bed) {
  StageSetup setup = settle;
  setup.sleeper->driven = {true, true, false};
  const double load = c.preparation.traffic_load, period = c.preparation.traffic_period;
  const int cycles = c.preparation.traffic_cycles;
  const double start = dem::box_bottom(*setup.sleeper);
  int cycle = 0;
  const StageDrive pulses = [&](dem::Simulation& sim, double t) {
    dem::RigidBox& box = sim.mutable_boxes()[0];
    box.applied_force = dem::Vec3(0.0, 0.0, -traffic_load_at(c.preparation, t));
    const int now = static_cast<int>(t / period);
    if (now > cycle && now < cycles && !control.quiet)
      // Over the progress line (redrawn with \r), on a line of its own.
      fmt::print(stderr, "\rtraffic: pulse {}/{} done, sleeper sunk {:.3f} mm\033[K\n", now, cycles,
                 1e3 * (start - dem::box_bottom(box)));
    cycle = now;
  };
  const Stage run = run_stage(c, bed.domain, bed.stones, setup, {"traffic", c.preparation.equilibrium_ratio,
                              cycles * period, bed.mean_size, RestCriterion::kFixedTime}, control.quiet,
                              control.stage_directory, pulses);
  bed.stones = body_states(run.sim);
  bed.sleeper_centre = run.sim.boxes()[0].centre;
  if (!control.quiet)
    fmt::print(stderr, "traffic: {} pulses of {:.3g} kN, sleeper sunk {:.3f} mm in all\n", cycles, 1e-3 * load,
               1e3 * (*run.report.sleeper_base_start - *run.report.sleeper_base));
  return run.report;
}

double traffic_load_at(const PreparationSettings& p, double t) {
  const double s = std::sin(std::numbers::pi * t / p.traffic_period);
  return p.traffic_load * s * s;
}

}  // namespace mfdem::railway
