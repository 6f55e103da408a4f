#include "studies/railway/preparation_stage.hpp"

#include <fmt/format.h>

#include <memory>
#include <string>

#include "dem/state_file.hpp"

namespace mfdem::railway {
namespace {

constexpr double kGravity = 9.81;  // m/s^2, the solver's default gravity

}  // namespace

CreepGoal settling_creep(const PushStudyConfig& c, double mean_size) {
  return {c.preparation.creep_ratio, c.preparation.creep_window, mean_size};
}

double lifting_energy(const std::vector<dem::ClumpSpec>& stones, double mean_size) {
  double mass = 0.0;
  for (const auto& s : stones) mass += s.mass;
  return mass * kGravity * mean_size;
}

Stage run_stage(const PushStudyConfig& c, const dem::Domain& domain, const std::vector<dem::ClumpSpec>& stones,
                const StageSetup& setup, const StageGoal& goal, bool quiet, const std::filesystem::path& stage_directory,
                const StageDrive& drive) {
  Stage stage{make_section_simulation(c, domain, stones, setup), {}};
  dem::Simulation& sim = stage.sim;
  sim.prepare();
  if (!quiet)
    fmt::print(stderr, "{}: time step {:.3g} s, {} x the stability limit {:.3g} s ({})\n", goal.name,
               sim.time_step(), c.time_step_safety, sim.time_step_limit().limit, sim.time_step_limit().reason);
  std::unique_ptr<dem::StateFile> frames;
  if (!stage_directory.empty())
    frames = std::make_unique<dem::StateFile>(stage_directory / (std::string(goal.name) + ".h5"), sim, goal.name);
  stage.report = run_until_settled(sim, goal.name, goal.ratio, lifting_energy(stones, goal.mean_size),
                                   goal.max_time, quiet, goal.criterion, frames.get(), 0.02, 2e-3, drive, goal.creep);
  if (setup.sleeper) {
    stage.report.sleeper_base_start = dem::box_bottom(*setup.sleeper);
    stage.report.sleeper_base = dem::box_bottom(sim.boxes()[0]);
  }
  return stage;
}

dem::RigidBox sleeper_box(const SectionGeometry& g) {
  dem::RigidBox box;
  box.name = "sleeper";
  box.half_extent = 0.5 * dem::Vec3(g.sleeper_length, g.sleeper_width, g.sleeper_height);
  box.centre = dem::Vec3(0.0, 0.5 * g.section_length, g.sleeper_base() + 0.5 * g.sleeper_height);
  box.mass = g.sleeper_mass;
  box.material = kSleeper;
  box.velocity = dem::Vec3::Zero();
  // Free across the track while it settles, as a sleeper cut from its rails for a push test:
  // it comes to rest where the lateral forces of the bed balance, so F(u = 0) is zero and not
  // a force locked in by holding it (the push resumes the contact springs of the packing).
  box.driven = {false, true, false};
  return box;
}

dem::RigidBox inset(dem::RigidBox box, double depth) {
  box.half_extent -= depth * kTampedAxes;
  return box;
}

dem::ClumpSpec scaled(dem::ClumpSpec stone, double f) {
  for (auto& p : stone.pebbles) {
    p.offset *= f;
    p.radius *= f;
  }
  stone.mass *= f * f * f;
  stone.principal_inertia *= f * f * f * f * f;
  return stone;
}

}  // namespace mfdem::railway
