#pragma once
// Seeded preparation of the ballast bed of a single-sleeper section.
//
// The procedure (every number a config key, see studies/presets/README.md):
// 1. Stones. Draw stone k = 0, 1, ... from the shape library and the grading with its own seeded
//    stream (fidelity::StoneSampler): template, sieve size, orientation. The count fills the
//    container below up to the ballast top at the expected solid fraction, times `overfill`.
// 2. Placement (stone_columns.hpp). Stones stand in columns over the container floor, each
//    dropped onto the pebbles below it with a 2 % gap, none touching, each starting down at
//    `drop_speed` x its height / the highest stone's: the columns collapse together, quicker
//    than a free fall from rest. The stones are then stored in Morton order of their positions
//    (dem/spatial_order.hpp), and again after the trimming (step 4): neighbours in space are
//    neighbours in memory, which makes a step of a large bed about 1.3x faster.
// 3. Deposition (compaction). Between the floor and container walls at the shoulder toes, with
//    the stone friction lowered to `deposition_friction` (a denser bed, as the "reduced
//    friction" compaction of PFC studies) and local damping `deposition_local_damping` (0.2:
//    PFC's 0.7 would make a stone fall at 0.3 g; without any, low-friction clumps keep
//    bouncing on the surface). The stage ends when the stones have landed: their kinetic energy
//    below `deposition_ratio` x the work of lifting them by one mean stone size (stage_runner.hpp),
//    or at `max_deposition_time`. Not the force ratio too: while low-friction clumps roll on the
//    surface it stays at 0.2-0.8 (standard and mini) and the stage always ran to its limit; the
//    settling (step 6) is where equilibrium is asked for.
// 4. Trimming and sleeper placement. Stones whose centre lies above the design surface (crib
//    and shoulder crest at the sleeper top, the shoulder slope beyond) or which intersect the
//    sleeper's volume are removed; the container walls go; the sleeper box is placed with its
//    base at depth_under_sleeper, held along the track, free across it and vertically (it
//    comes to rest where the bed's lateral forces balance, as a sleeper cut from its rails).
//    With `tamping_depth` > 0 the cut is that much shorter and narrower (sides and ends moved
//    in): stones that reach only into that shell of the sleeper's volume stay.
// 4b. Radius expansion (when `expansion_strain` > 0). The stones, drawn and deposited
//    1 / (1 + expansion_strain) of their size, grow back about their centres in
//    `expansion_steps` equal factors with the design friction and local damping, the sleeper (or
//    its tamping cut) in place: a bed with locked-in stress, as PFC users prepare one.
// 5. Tamping (when `tamping_depth` > 0). The sleeper, held across and along the track and free
//    vertically (or held at its design height: `tamping_sleeper_vertical = "held"`), with the
//    design friction and local damping `local_damping`, grows from the cut to its full size
//    over `tamping_time`:
//    its sides and ends push the stones in the shell into the cribs and shoulders, packing
//    them against it. Without it the sleeper stands in a hole up to a stone's size too large
//    and the crib stones lean loosely on it. The base is not pressed down (bed_preparation.cpp).
// 5b. Consolidation (when `consolidation_gravity` > 1). With the design friction and local
//    damping, the sleeper free across the track and vertically, gravity is raised that many
//    times for `consolidation_time`: the bed compacts under the heavier sleeper and stones, and
//    keeps part of that lateral stress when gravity returns to 1 g in the settling.
// 5c. Traffic (when `traffic_cycles` > 0). With the design friction and local damping, the
//    sleeper held across and along the track (as by its rails) and free vertically takes
//    `traffic_cycles` load pulses traffic_load x sin^2(pi t / traffic_period) downwards: the bed
//    under it compacts as under passing axles (its sinking is printed after every cycle).
// 6. Settling. With the design friction and local damping `local_damping`, the bed and the
//    sleeper (released: free across the track and vertically) settle under gravity until at
//    rest to `equilibrium_ratio`, or at `max_settling_time` (then the report says "settled NO"
//    and the command warns).
// After every stage but the last the bed can be saved and the preparation stopped, and resumed
// later (PreparationControl, preparation_checkpoint.hpp). Steps 4b-5c are in
// compaction_stages.hpp, the run of one stage in preparation_stage.hpp.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fidelity/policy.hpp"
#include "studies/railway/packing.hpp"
#include "studies/railway/preparation_checkpoint.hpp"
#include "studies/railway/stage_runner.hpp"

namespace mfdem::railway {

// How a preparation runs besides its config.
struct PreparationControl {
  bool quiet = false;
  // With it, each stage's states go to deposit.h5, settle.h5, ... (+ .xdmf) there.
  std::filesystem::path stage_directory;
  // With it, the bed is saved there after every stage but the last (preparation_checkpoint.hpp).
  std::filesystem::path checkpoint;
  bool resume = false;      // start from `checkpoint`, at the stage after the last one it holds
  // With it, start from this deposited bed (a checkpoint saved after the deposition, made with
  // this config but for the keys that act later), then trim and run this config's stages.
  std::filesystem::path deposit_from;
  std::string stop_after;   // a stage (stopping_points): stop once it and its checkpoint are done
  // With it, start from this finished packing (made with this config but for the traffic and
  // settling keys) and run this config's traffic and settling on it: more pulses on a bed
  // already prepared. Its stages are reported after the packing's own, named traffic_2,
  // settle_2, ... where the name was taken.
  std::filesystem::path continue_from;
  // With it, the deposited bed (fresh or from deposit_from) is converted by this policy before
  // the trimming (the policy sees the design sleeper), its balls grown into place with the
  // deposition's friction and walls (ball_growth.hpp), and every later stage runs on the model's
  // bed: the alternative conversion point of model_bed.hpp.
  std::optional<fidelity::Policy> convert_after_deposit;
  // Called once the inputs are checked (the stop, the checkpoint or packing to start from),
  // before the first stage runs: where a caller clears what the new bed replaces.
  std::function<void()> before_work;
};

// The stages a preparation with this config can stop after: "deposit", then those of expand,
// tamp, consolidate and traffic it runs (not the settling, which ends with the packing).
std::vector<std::string> stopping_points(const PushStudyConfig& config);

// The packing, or none when stopped by `control.stop_after`. Throws std::invalid_argument for
// geometry that cannot be built (railway::validate), a stop_after that is not a stage of it or a
// continue_from with a config that runs no traffic,
// std::runtime_error for a checkpoint that cannot be resumed (named), and dem::StabilityError
// when a stage becomes unstable. A resumed preparation is bitwise the uninterrupted one.
std::optional<Packing> prepare_bed(const PushStudyConfig& config, const PreparationControl& control,
                                   PreparationReport& report);

// The whole preparation in one go, without checkpoints.
Packing prepare_bed(const PushStudyConfig& config, bool quiet, PreparationReport& report,
                    const std::filesystem::path& stage_directory = {});

}  // namespace mfdem::railway
