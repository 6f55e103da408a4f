#include "studies/railway/model_bed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "dem/state_file.hpp"
#include "fidelity/shape_library.hpp"
#include "studies/railway/ball_growth.hpp"
#include "studies/railway/preparation_stage.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

double mean_size(const std::vector<StoneRecord>& stones) {
  double sum = 0.0;
  for (const auto& s : stones) sum += s.size;
  return sum / static_cast<double>(std::max<std::size_t>(1, stones.size()));
}

// The record of a conversion, before any growth or re-settling.
ModelReport converted_report(const PushStudyConfig& c, const fidelity::Policy& policy,
                             const fidelity::ConvertedBed& converted, const std::vector<StoneRecord>& stones) {
  ModelReport r;
  r.policy = policy.describe();
  r.rolling_friction = c.fidelity.rolling_friction;
  r.ball_friction = c.fidelity.ball_friction.value_or(c.ballast.friction);
  r.clumps = converted.clumps;
  r.balls = converted.balls;
  r.converted = converted.converted;
  r.elements = converted.elements_after;
  r.elements_before = all_clump_elements(c, converted.bodies, stones);
  r.springs_dropped = converted.springs_dropped;
  return r;
}

}  // namespace

fidelity::BedFrame bed_frame(const Packing& p) {
  fidelity::BedFrame f;
  f.floor_height = 0.0;  // section_simulation.cpp: the floor plane through the origin
  f.sleeper = p.sleeper;
  f.domain = p.domain;
  return f;
}

fidelity::Policy make_policy(const std::string& spec, const Packing& packing) {
  return fidelity::PolicyRegistry::builtin().make(spec, bed_frame(packing).scale());
}

std::int64_t all_clump_elements(const PushStudyConfig& c, const std::vector<dem::ClumpSpec>& bodies,
                                const std::vector<StoneRecord>& stones) {
  fidelity::ShapeLibrary custom;  // the shipped library is used in place, not copied
  const fidelity::ShapeLibrary& library =
      c.stones.library.empty() ? fidelity::standard_library() : (custom = fidelity::load_library(c.stones.library));
  std::int64_t n = 0;
  for (std::size_t k = 0; k < bodies.size(); ++k)
    n += bodies[k].material == kBall ? static_cast<std::int64_t>(library.templates.at(stones[k].template_index).pebbles.size())
                                     : static_cast<std::int64_t>(bodies[k].pebbles.size());
  return n;
}

std::optional<StageReport> model_preparation(const std::vector<StageReport>& stages) {
  const auto convert = std::find_if(stages.begin(), stages.end(), [](const StageReport& s) { return s.name == "convert"; });
  if (convert == stages.end()) return std::nullopt;
  StageReport sum;
  sum.name = "convert and later stages";
  for (auto s = convert; s != stages.end(); ++s) {
    sum.simulated_time += s->simulated_time;
    sum.steps += s->steps;
    sum.wall_seconds += s->wall_seconds;
    sum.unbalanced_force_ratio = s->unbalanced_force_ratio;
    sum.settled = s->settled;
    sum.settled_by_creep = s->settled_by_creep;
    if (s->sleeper_base) sum.sleeper_base = s->sleeper_base;
    if (s->sleeper_base_start && !sum.sleeper_base_start) sum.sleeper_base_start = s->sleeper_base_start;
  }
  return sum;
}

ModelBed model_bed(const Packing& packing, const PushStudyConfig& c, const fidelity::Policy& policy,
                   const ModelControl& control) {
  ModelBed out{packing, {}};
  const fidelity::ConvertedBed converted =
      fidelity::convert_bed(packing.bodies, packing.springs, policy, bed_frame(packing), c.ballast.density, kBall);
  ModelReport& r = out.report;
  r = converted_report(c, policy, converted, packing.stones);
  if (!packing.model.empty()) {  // converted while it was prepared (mfdem pack --fidelity)
    r.policy = converted.converted ? packing.model + " then " + r.policy : packing.model;
    r.conversion_point = packing.conversion_point;
  }
  if (converted.converted == 0) return out;  // bitwise the packing as prepared
  check_balls_fit(c, converted);
  if (!control.resettle) {
    out.packing.bodies = converted.bodies;
    out.packing.springs = converted.springs;
    r.conversion_point = "after preparation, not re-settled";
    return out;
  }

  r.conversion_point = "after preparation, re-settled";
  StageSetup settle;
  settle.stone_friction = c.ballast.friction;
  settle.ball_friction = c.fidelity.ball_friction;
  settle.stone_local_damping = c.preparation.local_damping;
  settle.sleeper = packing.sleeper;
  settle.sleeper->velocity = dem::Vec3::Zero();
  settle.sleeper->driven = {false, true, false};  // free across the track and vertically (stage_runner)
  if (!control.quiet)
    fmt::print(stderr, "model {}: {} of {} stones made balls ({} clumps, {} balls), {} -> {} elements; re-settling\n",
               r.policy, r.converted, converted.bodies.size(), r.clumps, r.balls, r.elements_before, r.elements);
  const std::filesystem::path frames_path =
      control.stage_directory.empty() ? std::filesystem::path() : control.stage_directory / "resettle.h5";
  const GrownBed grown = grow_balls(c, packing.domain, converted, settle, frames_path);
  r.reshaped = grown.reshaped;
  r.smallest_start_fraction = grown.smallest_start_fraction;
  r.mean_start_fraction = grown.mean_start_fraction;
  if (!control.quiet && grown.report.steps > 0)
    fmt::print(stderr, "grow: {} balls from {:.2f} (smallest) / {:.2f} (mean) of their radius to size over {} s, {}\n",
               r.reshaped, r.smallest_start_fraction, r.mean_start_fraction, c.fidelity.growth_time,
               scene::format_duration(grown.report.wall_seconds));
  if (grown.sleeper_centre) settle.sleeper->centre = *grown.sleeper_centre;

  dem::Simulation sim = make_section_simulation(c, packing.domain, grown.bodies, settle);
  sim.set_initial_springs(grown.springs);
  sim.prepare();
  std::unique_ptr<dem::StateFile> frames;
  if (!frames_path.empty())
    frames = std::make_unique<dem::StateFile>(frames_path, sim, fmt::format("re-settling of {} as {}", c.name, r.policy));
  try {
    const double size = mean_size(packing.stones);
    r.resettling = run_until_settled(sim, "resettle", c.preparation.equilibrium_ratio, lifting_energy(grown.bodies, size),
                                     c.preparation.max_settling_time, control.quiet, RestCriterion::kForcesAndEnergy,
                                     frames.get(), 0.02, 2e-3, {}, settling_creep(c, size));
  } catch (const dem::StabilityError&) {
    if (frames && sim.last_good_state()) frames->write_snapshot(sim, *sim.last_good_state(), "last good state");
    throw;
  }
  r.resettling->simulated_time += grown.report.simulated_time;
  r.resettling->steps += grown.report.steps;
  r.resettling->wall_seconds += grown.report.wall_seconds;
  r.resettling->sleeper_base_start = dem::box_bottom(packing.sleeper);
  r.resettling->sleeper_base = dem::box_bottom(sim.boxes()[0]);
  out.packing.bodies = body_states(sim);
  out.packing.sleeper = sim.boxes()[0];
  out.packing.sleeper.velocity = dem::Vec3::Zero();
  out.packing.springs = sim.contact_springs();
  out.packing.unbalanced_force_ratio = sim.unbalanced_force_ratio();
  out.packing.preparation_time += r.resettling->simulated_time;
  out.packing.model = r.policy;
  out.packing.conversion_point = r.conversion_point;
  return out;
}

}  // namespace mfdem::railway
