#pragma once
// Growing converted balls into a bed (the conversion's first stage, at either conversion point:
// model_bed.hpp). An equal-volume ball overlaps the neighbours where its clump sat; each starts at
// the radius at which it fits (fidelity::fitting_radii) and grows to its own at a steady rate
// over [fidelity] growth_time, in one simulation whose time step is the full-size bed's. The
// elastic energy the growth puts into contacts counts as work put in, so the energy guard still
// watches the run.
#include <filesystem>
#include <vector>

#include "fidelity/conversion.hpp"
#include "studies/railway/push_config.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stage_runner.hpp"

namespace mfdem::railway {

struct GrownBed {
  std::vector<dem::ClumpSpec> bodies;     // every ball at its own radius
  std::vector<dem::SpringState> springs;  // of the contacts at the end of the growth
  std::optional<dem::Vec3> sleeper_centre;  // where the growth left the sleeper (if the stage has one)
  StageReport report;                     // simulated time, steps, wall time of the growth
  std::int64_t reshaped = 0;              // balls that changed shape
  // Their starting radius as a fraction of their own: the smallest and the mean.
  double smallest_start_fraction = 1.0, mean_start_fraction = 1.0;
};

// Refuses (config::ConfigError, before any work) a converted bed whose largest ball is too wide
// for the periodic section: the crib (the sleeper's gap to its periodic image) must be wider than
// any element, and the neighbour search needs the section to hold two largest contact reaches
// (dem/neighbor_list.hpp); the message names the [section] key. On mini (a 0.08 m crib) 3 of 200
// seeds draw a stone whose ball is wider (up to 0.082 m): a policy that makes it a ball is refused.
void check_balls_fit(const PushStudyConfig& config, const fidelity::ConvertedBed& converted);

// Grows the reshaped balls of `converted` in the section `domain` with the boundaries, friction
// and damping of `setup` (growth_friction, when set, replaces the friction and takes away the
// balls' rolling resistance). Throws dem::StabilityError; with `last_good`, the converted bed is
// written there as the growth starts and an unstable growth adds its last good state.
GrownBed grow_balls(const PushStudyConfig& config, const dem::Domain& domain, const fidelity::ConvertedBed& converted,
                    StageSetup setup, const std::filesystem::path& last_good = {});

}  // namespace mfdem::railway
