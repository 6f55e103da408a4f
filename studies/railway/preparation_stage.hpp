#pragma once
// One stage of the bed preparation (bed_preparation.hpp): the section's solver run with the
// stage's boundaries and drive, until the bed is at rest or the stage's time is up; and the
// sleeper box and stone scaling the stages share.
#include <filesystem>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/railway/push_config.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stage_runner.hpp"

namespace mfdem::railway {

struct StageGoal {
  const char* name;
  double ratio;     // equilibrium target (stage_runner.hpp)
  double max_time;  // s
  double mean_size; // m, of the stones: the energy scale is their weight times it
  RestCriterion criterion;
  CreepGoal creep = {};  // with kForcesAndEnergy: the settling stages' second criterion
};

struct Stage {
  dem::Simulation sim;
  StageReport report;
};

// Sets up one preparation stage, prints its size and step (unless quiet), runs it until settled
// or its time limit, and writes its frames to stage_directory/NAME.h5 when a directory is given.
Stage run_stage(const PushStudyConfig& config, const dem::Domain& domain, const std::vector<dem::ClumpSpec>& stones,
                const StageSetup& setup, const StageGoal& goal, bool quiet, const std::filesystem::path& stage_directory,
                const StageDrive& drive = {});

// The settling stages' creep goal (config keys creep_ratio, creep_window) for stones of this mean size, m.
CreepGoal settling_creep(const PushStudyConfig& config, double mean_size);

// The work of lifting the stones by one mean stone size (m), J: the energy scale of "at rest".
double lifting_energy(const std::vector<dem::ClumpSpec>& stones, double mean_size);

// The sleeper at its design place: held along the track, free across it and vertically.
dem::RigidBox sleeper_box(const SectionGeometry& geometry);

// Tamping works on the sides and ends: the faces that grow into the bed. Not the base: under
// the sleeper the bed is confined by the floor, and pressing the base down by even 10 mm stores
// so much elastic energy that the released sleeper is thrown up (mini: a 6 kg sleeper rose 57 mm
// after 10 mm and 0.9 m after 20 mm).
inline const dem::Vec3 kTampedAxes(1.0, 1.0, 0.0);
// The box with its sides and ends moved in by `depth`, m.
dem::RigidBox inset(dem::RigidBox box, double depth);

// The stone grown (f > 1) or shrunk about its centre of mass: same shape, density and frame.
dem::ClumpSpec scaled(dem::ClumpSpec stone, double f);

}  // namespace mfdem::railway
