#pragma once
// The configuration of a single-sleeper push study: the section, the stones, the materials, the
// bed preparation and the push. Read from a TOML file; the shipped presets (mini, study, standard,
// paper) are such files in studies/presets/, and every key is documented in
// studies/presets/README.md.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dem/material.hpp"
#include "dem/stability.hpp"
#include "fidelity/policy.hpp"
#include "studies/railway/section_geometry.hpp"

namespace mfdem::railway {

struct StoneSettings {
  std::filesystem::path library;       // clump templates; empty: the shipped 6-pebble library
  // How the stones are drawn and prepared: clumps (the reference model) or all balls. A
  // multi-layer model converts a prepared all-clump bed instead ([fidelity]).
  fidelity::Representation representation = fidelity::Representation::clump;
  double solid_fraction = 0.58;        // expected in the settled bed: sizes the number of stones
  double overfill = 1.10;              // stones generated / stones expected in the profile
  double fixed_size = 0.0;             // m; > 0: every stone has this sieve size (tests), else graded
};

// Bed preparation (see bed_preparation.hpp for the procedure).
struct PreparationSettings {
  double deposition_friction = 0.1;   // stone-stone mu while depositing: a denser bed
  double drop_speed = 6.0;            // m/s downward of the highest stone as deposition starts
  double deposition_local_damping = 0.2;  // alpha while depositing (0.7 would slow free fall to 0.3 g)
  double local_damping = 0.7;         // alpha of the stones while settling
  double deposition_ratio = 1e-2;     // deposition ends when kinetic energy / (M g d_mean) is below this
  double equilibrium_ratio = 1e-3;    // the bed is settled when the ratio is below this
  double max_deposition_time = 1.5;   // s of simulated time, a limit
  double max_settling_time = 1.0;     // s, a limit for each settling stage
  // A settling stage also ends when the kinetic condition holds and the stones' mean
  // displacement over `creep_window` (s) is below creep_ratio times their mean size
  // (stage_runner.hpp); 0 leaves the force ratio as the only criterion.
  double creep_ratio = 0.0;
  double creep_window = 0.05;
  // m: the sleeper is cut into the bed this much shorter and narrower on each side, then grows
  // to its size over `tamping_time` (s), pushing the stones beside it into the cribs and
  // shoulders, packing them against it; 0 cuts the full size out and leaves the gaps.
  double tamping_depth = 0.0;
  double tamping_time = 0.1;
  // While tamping the sleeper is free vertically (it sinks onto the bed) or held at its design
  // height, as a tamping machine holds the lifted track while its tines squeeze the ballast.
  bool tamping_sleeper_held = false;
  // Consolidation: for `consolidation_time` (s) the bed and the sleeper weigh this many times
  // their weight, then settle at 1 g: an overconsolidated bed, whose stones keep part of the
  // lateral stress of the heavy phase (as a bed compacted by traffic); 1 skips the stage.
  double consolidation_gravity = 1.0;
  double consolidation_time = 0.1;
  // Radius expansion, as PFC users prepare beds: the stones are deposited 1 / (1 + strain) of
  // their size and grown back, about their centres, once the sleeper is in place, in
  // `expansion_steps` equal factors over `expansion_time` (s), to lock stress into the bed; 0
  // skips it. (On the standard bed the stress left through the free surfaces: results/push_test.)
  double expansion_strain = 0.0;
  int expansion_steps = 20;
  double expansion_time = 0.1;
  // Traffic: `traffic_cycles` load pulses on the sleeper, each traffic_load x sin^2(pi t /
  // traffic_period) downwards (N, s), the sleeper held across and along the track (by the rails)
  // and free vertically: the bed compacts under the sleeper as under passing axles. 0 skips it.
  int traffic_cycles = 0;
  double traffic_load = 90e3;   // N: two rail seats, each about 45 % of a 100 kN wheel (a 20 t axle)
  double traffic_period = 0.05; // s: one axle at about 100 km/h passes a sleeper in about this
};

struct PushSettings {
  double velocity = 0.05;          // m/s, lateral (+x) sleeper speed
  double distance = 5e-3;          // m, u_end
  double record_interval = 1e-5;   // m of sleeper displacement between F(u) samples
  double ramp_distance = 1e-4;     // m over which the sleeper speeds up from rest (no impact start)
  // alpha of the stones during the push. Zero: PFC local damping resists every acceleration along
  // the motion (a stone speeds up at (1 - alpha) F / m), so the stones ahead of the sleeper lag and
  // F(u) depends on the speed. On the standard bed, halving 50 mm/s lowered the mean F of the first
  // millimetre by 13 % with alpha 0.7 and by 3.4 % with 0 (results/push_test/README.md). The
  // viscous contact damping (damping_ratio) still takes out the rattle.
  double local_damping = 0.0;
  int network_samples = 50;        // inertial-number and stress samples during the push
  // The sleeper's vertical motion: free under its own weight (the default, as a sleeper of an
  // unloaded track), or held at its settled height ("held", as a PFC wall sleeper driven only
  // across the track): the base then carries what the bed's dilation or contraction gives it,
  // not the sleeper's weight.
  bool sleeper_held_vertically = false;
};

// The model a push runs: the fidelity policy that converts the prepared bed (fidelity/policy.hpp)
// and the ball material. Balls are the material "ball": the ballast's, with this rolling
// friction and friction; a ball-ball contact has them, a ball-clump contact the smaller of the
// two materials' values (rolling friction 0 unless the ballast has one), unless a [[pair]] says
// otherwise.
struct FidelitySettings {
  std::string policy = "all-clump";  // NAME[:key=value,...], checked against the design geometry
  double rolling_friction = 0.3;     // mu_r of the balls (Table 1: ball-ball contacts)
  std::optional<double> ball_friction;  // mu of the balls in the settling and push; default the ballast's
  // The re-settling first grows the balls from the radius at which they fit (fidelity::
  // fitting_radii) to their own at a steady rate over growth_time (s), with growth_friction
  // (none: the design friction and the balls' rolling friction; a value: that mu for every stone
  // and no rolling resistance, as the deposition's lowered friction).
  double growth_time = 0.1;
  std::optional<double> growth_friction;
};

struct PushStudyConfig {
  std::filesystem::path source;     // the file it came from
  std::string text;                 // its contents, kept in the packing for reproduction
  std::string name;                 // preset or file stem
  std::uint64_t seed = 1;
  SectionGeometry geometry;
  StoneSettings stones;
  dem::Material ballast, sleeper, floor;
  // [[pair]] overrides between two different materials (e.g. a rougher stone-sleeper interface);
  // they hold in every stage of the preparation and in the push.
  std::vector<dem::PairOverride> pairs;
  PreparationSettings preparation;
  PushSettings push;
  FidelitySettings fidelity;
  double time_step_safety = 0.2;    // automatic step = safety x critical step
  dem::GuardSettings guards;
};

// A preset name (mini, study, standard, paper) or a path to a TOML file. Throws config::ConfigError
// naming file, line, key, value and expectation; std::runtime_error for an unknown preset.
PushStudyConfig load_push_config(const std::string& preset_or_file);
// Parses a config held in memory (from a packing file); `source` names it in messages.
PushStudyConfig parse_push_config(const std::string& text, const std::filesystem::path& source);

// The directory of the shipped presets.
std::filesystem::path preset_directory();

}  // namespace mfdem::railway
