#include "studies/railway/model_bed.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "dem/state_file.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

constexpr double kGravity = 9.81;  // m/s^2, the solver's default
// A ball never starts below this fraction of its radius (a clump flat on the floor has its
// centre low; growing from less would take long and gain nothing).
constexpr double kSmallestStartFraction = 0.5;

double lifting_energy(const std::vector<dem::ClumpSpec>& stones, const std::vector<StoneRecord>& records) {
  double mass = 0.0, size = 0.0;
  for (const auto& s : stones) mass += s.mass;
  for (const auto& r : records) size += r.size;
  return mass * kGravity * size / static_cast<double>(std::max<std::size_t>(1, records.size()));
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

ModelBed model_bed(const Packing& packing, const PushStudyConfig& c, const fidelity::Policy& policy,
                   const ModelControl& control) {
  ModelBed out{packing, {}};
  ModelReport& r = out.report;
  r.policy = policy.describe();
  r.rolling_friction = c.fidelity.rolling_friction;
  r.ball_friction = c.fidelity.ball_friction.value_or(c.ballast.friction);
  const fidelity::ConvertedBed converted =
      fidelity::convert_bed(packing.bodies, packing.springs, policy, bed_frame(packing), c.ballast.density, kBall);
  r.clumps = converted.clumps;
  r.balls = converted.balls;
  r.converted = converted.converted;
  r.elements = converted.elements_after;
  r.elements_before = converted.elements_before;
  r.springs_dropped = converted.springs_dropped;
  if (converted.converted == 0) return out;  // bitwise the packing as prepared
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

  // The balls start where they fit and grow to size at a steady rate over growth_time; the time
  // step is the one of the full-size bed.
  const fidelity::BedFrame frame = bed_frame(packing);
  const std::vector<double> start = fidelity::fitting_radii(converted, frame, kSmallestStartFraction);
  std::vector<dem::ClumpSpec> bodies = converted.bodies;
  std::vector<dem::SpringState> springs = converted.springs;
  r.smallest_start_fraction = 1.0;
  double fraction_sum = 0.0;
  std::vector<std::pair<dem::Index, double>> growing;  // element (= first element of the body), full radius
  dem::Index first_element = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const dem::Index element = first_element;
    first_element += static_cast<dem::Index>(bodies[b].pebbles.size());
    if (!converted.reshaped[b]) continue;
    const double full = bodies[b].pebbles.front().radius;
    r.smallest_start_fraction = std::min(r.smallest_start_fraction, start[b] / full);
    fraction_sum += start[b] / full;
    ++r.reshaped;
    if (start[b] < full) growing.emplace_back(element, full);
    bodies[b].pebbles.front().radius = start[b];
  }
  r.mean_start_fraction = r.reshaped ? fraction_sum / static_cast<double>(r.reshaped) : 1.0;
  const auto keep_last_good = [&](dem::Simulation& sim, auto&& body) {
    try {
      return body();
    } catch (const dem::StabilityError&) {
      if (!control.stage_directory.empty() && sim.last_good_state()) {
        dem::StateFile last(control.stage_directory / "resettle.h5", sim,
                            fmt::format("re-settling of {} as {}: last good state", c.name, r.policy));
        last.write_snapshot(sim, *sim.last_good_state(), "last good state");
      }
      throw;
    }
  };
  StageReport growth;
  if (!growing.empty()) {
    StageSetup grow = settle;
    if (c.fidelity.growth_friction) {
      grow.stone_friction = *c.fidelity.growth_friction;
      grow.ball_friction = *c.fidelity.growth_friction;
      grow.ball_rolling_friction = 0.0;
    }
    grow.time_step = c.time_step_safety *
                     make_section_simulation(c, packing.domain, converted.bodies, settle).stability_limit().limit;
    dem::Simulation sim = make_section_simulation(c, packing.domain, bodies, grow);
    sim.set_initial_springs(springs);
    sim.prepare();
    std::vector<double> from;
    for (const auto& [element, full] : growing) from.push_back(sim.elements().radius[element]);
    const double duration = c.fidelity.growth_time;
    const StageDrive drive = [&](dem::Simulation& s, double t) {
      const double share = std::min(1.0, (t + s.time_step()) / duration);  // reached by the step's end
      for (std::size_t k = 0; k < growing.size(); ++k)
        s.set_element_radius(growing[k].first, from[k] + share * (growing[k].second - from[k]));
    };
    growth = keep_last_good(sim, [&] {
      return run_until_settled(sim, "grow", c.preparation.equilibrium_ratio, 1.0, duration, true,
                               RestCriterion::kFixedTime, nullptr, 0.02, 2e-3, drive);
    });
    bodies = body_states(sim);
    // Exactly their own radii (the last step may fall short of growth_time by round-off).
    for (std::size_t b = 0; b < bodies.size(); ++b) bodies[b].pebbles = converted.bodies[b].pebbles;
    springs = sim.contact_springs();
    settle.sleeper->centre = sim.boxes()[0].centre;
    if (!control.quiet)
      fmt::print(stderr, "grow: {} balls from {:.2f} (smallest) / {:.2f} (mean) of their radius to size over {} s, {}\n",
                 r.reshaped, r.smallest_start_fraction, r.mean_start_fraction, duration,
                 scene::format_duration(growth.wall_seconds));
  }

  dem::Simulation sim = make_section_simulation(c, packing.domain, bodies, settle);
  sim.set_initial_springs(springs);
  sim.prepare();
  std::unique_ptr<dem::StateFile> frames;
  if (!control.stage_directory.empty())
    frames = std::make_unique<dem::StateFile>(control.stage_directory / "resettle.h5", sim,
                                              fmt::format("re-settling of {} as {}", c.name, r.policy));
  r.resettling = keep_last_good(sim, [&] {
    return run_until_settled(sim, "resettle", c.preparation.equilibrium_ratio, lifting_energy(bodies, packing.stones),
                             c.preparation.max_settling_time, control.quiet, RestCriterion::kForcesAndEnergy,
                             frames.get());
  });
  r.resettling->simulated_time += growth.simulated_time;
  r.resettling->steps += growth.steps;
  r.resettling->wall_seconds += growth.wall_seconds;
  r.resettling->sleeper_base_start = dem::box_bottom(packing.sleeper);
  r.resettling->sleeper_base = dem::box_bottom(sim.boxes()[0]);
  out.packing.bodies = body_states(sim);
  out.packing.sleeper = sim.boxes()[0];
  out.packing.sleeper.velocity = dem::Vec3::Zero();
  out.packing.springs = sim.contact_springs();
  out.packing.unbalanced_force_ratio = sim.unbalanced_force_ratio();
  out.packing.preparation_time += r.resettling->simulated_time;
  return out;
}

}  // namespace mfdem::railway
