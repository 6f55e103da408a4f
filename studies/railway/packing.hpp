#pragma once
// A prepared ballast bed under its sleeper: the result of `mfdem pack`, the start of every push.
//
// Saved as an mfdem state file (one frame: the settled bodies, readable by h5py and, through the
// .xdmf beside it, by ParaView; layout in dem/state_file.hpp) plus a /packing group:
//   /packing                attrs: format = "mfdem-packing-1", seed, config (the TOML text it was
//                           made from), config_source, preparation_time (s),
//                           unbalanced_force_ratio (at the end), domain_min, domain_max,
//                           periodic_y (1 or 0), sleeper_centre, sleeper_half_extent (m),
//                           sleeper_mass (kg), continued_from (the packing whose bed got more
//                           traffic, `mfdem pack --continue-from`; absent otherwise), model and
//                           conversion_point (the fidelity policy that made its balls and when,
//                           model_bed.hpp; absent for a bed as drawn), with model_rolling_friction
//                           and model_ball_friction (the balls' material as made; a push of the
//                           packing takes them unless given other ones)
//   /packing/stone_id       [bodies]  index of the stone's seeded draw (fidelity::StoneSampler)
//   /packing/template       [bodies]  index of its template in the shape library
//   /packing/size           [bodies]  sieve size d, m
//   /packing/springs/       the springs of the active contacts at the end of the settling
//                           (dem::SpringState): kind [n] (0 stone-stone, 1 wall, 2 sleeper),
//                           first, second [n] (element, element / wall / box index),
//                           shear_force, rolling_moment [n x 3] (N, N m), damping_force [n] (N).
//                           A push resumes them, so the bed starts with the friction forces that
//                           hold it. Packings written before they were kept have no group and
//                           start from unloaded springs.
//   /packing/stages/NAME/   of each preparation stage (written by append_stage_reports): attrs
//                           simulated_time, steps, settled (1/0), settled_by_creep (1 when the
//                           creep goal ended it; absent otherwise), wall_seconds,
//                           end_unbalanced_force_ratio, order (0, 1, ...: the order they ran,
//                           as HDF5 lists groups by name), sleeper_base and sleeper_base_start
//                           (m, at the stage's end and start, once the sleeper is placed); at each
//                           equilibrium check [n]: time (s since the stage began),
//                           unbalanced_force_ratio, kinetic_ratio (kinetic energy / M g d),
//                           sleeper_base (m; once the sleeper is in the bed), creep (the stones'
//                           mean displacement over creep_window / their mean size; with a creep goal).
// Every number is stored as the double the solver held, so a push from the file is bitwise the
// push from memory.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/railway/push_config.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stage_runner.hpp"

namespace mfdem::railway {

struct StoneRecord {
  std::int64_t id = 0;     // draw index
  int template_index = 0;
  double size = 0.0;       // m
};

struct Packing {
  PushStudyConfig config;
  std::vector<StoneRecord> stones;      // one per body
  std::vector<dem::ClumpSpec> bodies;   // their state (a ball is a one-pebble clump at its centre)
  dem::RigidBox sleeper;
  dem::Domain domain;
  double preparation_time = 0.0;        // s simulated
  double unbalanced_force_ratio = 0.0;  // at the end of preparation
  std::vector<dem::SpringState> springs;  // of its active contacts, element-indexed
  // The packing this one was continued from (`mfdem pack --continue-from`), as given; "" if none.
  std::string continued_from;
  // The fidelity policy that made its balls and when ("" for a bed as drawn): a model's bed.
  std::string model, conversion_point;

  std::int64_t element_count() const;
};

// The bodies of a simulation (all but its boxes) as ClumpSpecs, exactly as held.
std::vector<dem::ClumpSpec> body_states(const dem::Simulation& sim);

// Writes `path` (and path.xdmf).
void save_packing(const std::filesystem::path& path, const Packing& packing);
// The same, the frame's contact forces evaluated with the packing's sleeper (when `setup` has one)
// and the other boundaries of `setup` (the bed of a stage before the sleeper is in:
// preparation_checkpoint.hpp); `what` starts the file's note.
void save_packing(const std::filesystem::path& path, const Packing& packing, const StageSetup& setup,
                  const std::string& what);
// Adds the preparation stages' reports to a saved packing (/packing/stages).
void append_stage_reports(const std::filesystem::path& path, const std::vector<StageReport>& stages);
// The finished packing and its stage reports: written beside `path` (.partial.h5) and renamed
// over it with its .xdmf, so that a run stopped while writing leaves no packing.h5 that lacks
// part of it.
void save_finished_packing(const std::filesystem::path& path, const Packing& packing,
                           const std::vector<StageReport>& stages);
// The path a packing or checkpoint is written to before it is renamed to `path`.
std::filesystem::path partial_path(const std::filesystem::path& path);
// The stage reports of a saved packing, in the order they ran (none for an older packing).
std::vector<StageReport> read_stage_reports(const std::filesystem::path& path);
// Throws std::runtime_error naming the file and what is missing.
// The stage a preparation checkpoint (preparation_checkpoint.hpp) was saved before, or nothing
// for a finished packing (or a file that is neither: load_packing says what is wrong with it).
std::optional<std::string> checkpoint_stage(const std::filesystem::path& path);
Packing load_packing(const std::filesystem::path& path);

}  // namespace mfdem::railway
