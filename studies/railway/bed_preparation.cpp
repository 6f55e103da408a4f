#include "studies/railway/bed_preparation.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include "dem/spatial_order.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stone_columns.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

constexpr double kGravity = 9.81;          // m/s^2, the solver's default gravity
bool intersects_box(const dem::ClumpSpec& stone, const dem::RigidBox& box) {
  for (const auto& p : stone.pebbles) {
    const dem::Vec3 x = stone.position + stone.orientation.normalized() * p.offset;
    if (dem::sphere_box_contact(x, p.radius, box.centre, box.half_extent)) return true;
  }
  return false;
}

// Tamping works on the sides and ends: the faces that grow into the bed. Not the base: under
// the sleeper the bed is confined by the floor, and pressing the base down by even 10 mm stores
// so much elastic energy that the released sleeper is thrown up (mini: a 6 kg sleeper rose 57 mm
// after 10 mm and 0.9 m after 20 mm).
const dem::Vec3 kTampedAxes(1.0, 1.0, 0.0);

// The box with its sides and ends moved in by `depth`, m.
dem::RigidBox inset(dem::RigidBox box, double depth) {
  box.half_extent -= depth * kTampedAxes;
  return box;
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

// The work of lifting the stones by one mean stone size, J: the energy scale of "at rest".
double lifting_energy(const std::vector<dem::ClumpSpec>& stones, double mean_size) {
  double mass = 0.0;
  for (const auto& s : stones) mass += s.mass;
  return mass * kGravity * mean_size;
}

struct StageGoal {
  const char* name;
  double ratio;     // equilibrium target (stage_runner.hpp)
  double max_time;  // s
  double mean_size; // m, of the stones: the energy scale is their weight times it
  RestCriterion criterion;
};

struct Stage {
  dem::Simulation sim;
  StageReport report;
};

// Sets up one preparation stage, prints its size and step, runs it until settled or its time
// limit, and writes its frames to stage_directory/NAME.h5 when a directory is given.
Stage run_stage(const PushStudyConfig& c, const dem::Domain& domain, const std::vector<dem::ClumpSpec>& stones,
                const StageSetup& setup, const StageGoal& goal, bool quiet, const std::filesystem::path& stage_directory,
                const StageDrive& drive = {}) {
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
                                   goal.max_time, quiet, goal.criterion, frames.get(), 0.02, 2e-3, drive);
  if (setup.sleeper) stage.report.sleeper_base = dem::box_bottom(sim.boxes()[0]);
  return stage;
}

double highest_point(const std::vector<dem::ClumpSpec>& bodies) {
  double top = 0.0;
  for (const auto& b : bodies)
    for (const auto& p : b.pebbles) top = std::max(top, b.position.z() + p.offset.norm() + p.radius);
  return top;
}

// The stone grown (f > 1) or shrunk about its centre of mass: same shape, density and frame.
dem::ClumpSpec scaled(dem::ClumpSpec stone, double f) {
  for (auto& p : stone.pebbles) {
    p.offset *= f;
    p.radius *= f;
  }
  stone.mass *= f * f * f;
  stone.principal_inertia *= f * f * f * f * f;
  return stone;
}

std::vector<dem::Vec3> positions_of(const std::vector<dem::ClumpSpec>& bodies) {
  std::vector<dem::Vec3> x;
  for (const auto& b : bodies) x.push_back(b.position);
  return x;
}

// Step 4b, radius expansion: grows the stones back to their drawn size in equal factors, the
// bed moving for an equal time after each (each a solver run of its own: radii are fixed within
// a run; contact springs restart and reload within micrometres of slip), the sleeper's tamping
// cut (the sleeper itself without tamping) in place.
StageReport expand(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
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
StageReport tamp(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
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
StageReport consolidate(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
                        BedBetweenStages& bed) {
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
StageReport traffic(const PushStudyConfig& c, const StageSetup& settle, const PreparationControl& control,
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
      fmt::print(stderr, "traffic: cycle {}/{} done, sleeper sunk {:.3f} mm\n", now, cycles,
                 1e3 * (start - dem::box_bottom(box)));
    cycle = now;
  };
  const Stage run = run_stage(c, bed.domain, bed.stones, setup, {"traffic", c.preparation.equilibrium_ratio,
                              cycles * period, bed.mean_size, RestCriterion::kFixedTime}, control.quiet,
                              control.stage_directory, pulses);
  bed.stones = body_states(run.sim);
  bed.sleeper_centre = run.sim.boxes()[0].centre;
  if (!control.quiet)
    fmt::print(stderr, "traffic: {} cycles of {:.3g} kN, sleeper sunk {:.3f} mm in all\n", cycles, 1e-3 * load,
               1e3 * (start - dem::box_bottom(run.sim.boxes()[0])));
  return run.report;
}

// Between the floor and container walls at the shoulder toes, with lowered stone friction.
StageSetup deposition_setup(const PushStudyConfig& c) {
  StageSetup deposit;
  deposit.stone_friction = c.preparation.deposition_friction;
  deposit.stone_local_damping = c.preparation.deposition_local_damping;
  deposit.container_walls = true;
  return deposit;
}

// Steps 1-3: draws the stones and deposits them.
BedBetweenStages deposit(const PushStudyConfig& c, bool quiet, PreparationReport& report,
                         const std::filesystem::path& stage_directory) {
  const SectionGeometry& g = c.geometry;
  const StoneFactory factory(c);
  // Step 1: how many stones fill the container to the ballast top.
  constexpr int kVolumeSample = 2000;
  const double mean_volume = factory.mean_volume(kVolumeSample);
  validate(g, factory.upper_size());
  const double container = 2.0 * g.toe_half_width() * g.section_length * g.ballast_top();
  const auto count = static_cast<std::int64_t>(std::ceil(c.stones.overfill * c.stones.solid_fraction * container / mean_volume));
  std::vector<DrawnStone> drawn(count);
  for (std::int64_t k = 0; k < count; ++k) drawn[k] = factory.draw(k);
  // Radius expansion: deposited small, grown back to size in step 4b.
  const double expansion = 1.0 + c.preparation.expansion_strain;
  for (auto& s : drawn) s.body = scaled(s.body, 1.0 / expansion);
  drawn = place_in_columns(c, std::move(drawn));
  BedBetweenStages bed;
  for (const auto& s : drawn) bed.mean_size += s.record.size / static_cast<double>(count);
  report.stones_generated = count;

  std::vector<dem::ClumpSpec> bodies;
  for (const auto& s : drawn) bodies.push_back(s.body);
  // Stored in space order: neighbours in space are neighbours in memory (dem/spatial_order.hpp).
  const std::vector<dem::Index> placed_order = dem::morton_order(positions_of(bodies), bed.mean_size);
  drawn = dem::permuted(drawn, placed_order);
  bodies = dem::permuted(bodies, placed_order);
  bed.domain = section_domain(c, highest_point(bodies) + 0.1);

  // Step 3: deposition with lowered friction inside the container.
  const Stage deposition = run_stage(c, bed.domain, bodies, deposition_setup(c),
                                     {"deposit", c.preparation.deposition_ratio, c.preparation.max_deposition_time,
                                      bed.mean_size, RestCriterion::kEnergyOnly}, quiet, stage_directory);
  report.time_step = deposition.sim.time_step();
  report.stages.push_back(deposition.report);
  bed.stones = body_states(deposition.sim);
  for (const auto& s : drawn) bed.records.push_back(s.record);
  bed.sleeper_centre = sleeper_box(g).centre;
  return bed;
}

// Step 4: trims the deposited bed to the profile and cuts the sleeper's place (tamping_depth
// shorter and narrower).
void trim(const PushStudyConfig& c, BedBetweenStages& bed, PreparationReport& report) {
  const SectionGeometry& g = c.geometry;
  const dem::RigidBox cut = inset(sleeper_box(g), c.preparation.tamping_depth);
  std::vector<dem::ClumpSpec> kept;
  std::vector<StoneRecord> records;
  for (std::size_t k = 0; k < bed.stones.size(); ++k) {
    const dem::ClumpSpec& s = bed.stones[k];
    if (s.position.z() > g.surface_height(s.position.x())) continue;
    if (intersects_box(s, cut)) continue;
    kept.push_back(s);
    records.push_back(bed.records[k]);
  }
  report.stones_removed = report.stones_generated - static_cast<std::int64_t>(kept.size());
  // The columns have collapsed: store the kept stones in space order again.
  const std::vector<dem::Index> order = dem::morton_order(positions_of(kept), bed.mean_size);
  bed.stones = dem::permuted(kept, order);
  bed.records = dem::permuted(records, order);
  bed.trimmed = true;
}

// A stage after the trimming; the settling (run == nullptr) ends every preparation.
using StageRun = StageReport (*)(const PushStudyConfig&, const StageSetup&, const PreparationControl&,
                                 BedBetweenStages&);
struct LaterStage {
  std::string name;
  double max_time;  // s simulated, at most
  StageRun run;
};

// The stages after the deposition, in the order they run: those the config asks for.
std::vector<LaterStage> later_stages(const PushStudyConfig& c) {
  const PreparationSettings& p = c.preparation;
  std::vector<LaterStage> stages;
  if (p.expansion_strain > 0.0) stages.push_back({"expand", p.expansion_time, expand});
  if (p.tamping_depth > 0.0) stages.push_back({"tamp", p.tamping_time, tamp});
  if (p.consolidation_gravity > 1.0) stages.push_back({"consolidate", p.consolidation_time, consolidate});
  if (p.traffic_cycles > 0) stages.push_back({"traffic", p.traffic_cycles * p.traffic_period, traffic});
  stages.push_back({"settle", p.max_settling_time, nullptr});
  return stages;
}

std::vector<std::string> names_of(const std::vector<LaterStage>& stages) {
  std::vector<std::string> names;
  for (const auto& s : stages) names.push_back(s.name);
  return names;
}

// After a stage: what is left and about how long it takes, at the finished stage's cost per
// body and step (every stage has the deposition's time step). A paper-size pack runs for hours.
void print_remaining(const std::vector<LaterStage>& stages, std::size_t next, const PreparationReport& report,
                     std::size_t bodies_before, std::size_t bodies_after) {
  const StageReport& last = report.stages.back();
  double time = 0.0;
  for (std::size_t k = next; k < stages.size(); ++k) time += stages[k].max_time;
  const auto steps = static_cast<double>(std::llround(time / report.time_step));
  const double per_step = last.wall_seconds / std::max<double>(1.0, static_cast<double>(last.steps)) *
                          static_cast<double>(bodies_after) / static_cast<double>(std::max<std::size_t>(1, bodies_before));
  const std::vector<std::string> names = names_of(stages);
  std::vector<std::string> left(names.begin() + static_cast<std::ptrdiff_t>(next), names.end());
  fmt::print(stderr, "pack: {} done in {}; left: {}, at most {:.3g} s simulated ({:.0f} steps), at most about {} at its speed\n",
             last.name, scene::format_duration(last.wall_seconds), fmt::join(left, ", "), time, steps,
             scene::format_duration(per_step * steps));
}

}  // namespace

double traffic_load_at(const PreparationSettings& p, double t) {
  const double s = std::sin(std::numbers::pi * t / p.traffic_period);
  return p.traffic_load * s * s;
}

std::vector<std::string> stopping_points(const PushStudyConfig& c) {
  std::vector<std::string> names = names_of(later_stages(c));
  names.pop_back();  // the settling ends with the packing itself
  names.insert(names.begin(), "deposit");
  return names;
}

std::optional<Packing> prepare_bed(const PushStudyConfig& c, const PreparationControl& control,
                                   PreparationReport& report) {
  const std::size_t first_stage = report.stages.size();
  const std::vector<LaterStage> stages = later_stages(c);
  const std::vector<std::string> names = names_of(stages);
  const std::vector<std::string> points = stopping_points(c);
  const auto stop_index = static_cast<std::size_t>(std::find(points.begin(), points.end(), control.stop_after) - points.begin());
  if (!control.stop_after.empty() && stop_index == points.size())
    throw std::invalid_argument(fmt::format("--stop-after {}: not a stage this config stops after (expected "
                                            "one of: {})", control.stop_after, fmt::join(points, ", ")));
  const dem::RigidBox sleeper = sleeper_box(c.geometry);
  BedBetweenStages bed;
  // After each stage but the last: the checkpoint, and a stop when asked for.
  const auto done = [&](const std::string& stage, const std::string& following) {
    if (!control.checkpoint.empty()) {
      StageSetup setup = deposition_setup(c);  // the deposited bed's boundaries
      if (bed.trimmed) {
        setup = {};
        const bool cut = following == "expand" || following == "tamp";
        setup.sleeper = cut ? inset(sleeper, c.preparation.tamping_depth) : sleeper;
      }
      save_checkpoint(control.checkpoint, c, bed, setup, report, following);
    }
    return control.stop_after == stage;
  };
  std::size_t next = 0;  // into `stages`
  const bool reuse = !control.deposit_from.empty();
  if (control.resume || reuse) {
    const std::filesystem::path& from = reuse ? control.deposit_from : control.checkpoint;
    std::string name;
    bed = load_checkpoint(from, c, reuse ? CheckpointUse::kDeposit : CheckpointUse::kResume, report, name);
    if (reuse) name = names.front();  // this config's own stages follow the deposition
    next = static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
    if (next == names.size())
      throw std::runtime_error(fmt::format("{}: next_stage '{}' is not a stage of this config ({})", from.string(),
                                           name, fmt::join(names, ", ")));
    // points[i] is stages[i - 1] for i >= 1: done when i - 1 < next.
    if (!control.stop_after.empty() && stop_index <= next)
      throw std::invalid_argument(fmt::format("--stop-after {}: already done in {} (its next stage is '{}')",
                                              control.stop_after, from.string(), name));
    if (!control.quiet)
      fmt::print(stderr, "{} {}: {} stones, next stage '{}'\n", reuse ? "deposited bed from" : "resuming from",
                 from.string(), bed.stones.size(), name);
  } else {
    bed = deposit(c, control.quiet, report, control.stage_directory);
    if (done("deposit", names.front())) return std::nullopt;
  }
  if (!bed.trimmed) {
    trim(c, bed, report);
    if (!control.quiet && next == 0)
      print_remaining(stages, 0, report, static_cast<std::size_t>(report.stones_generated), bed.stones.size());
  }

  // The design friction and local damping, the sleeper free across the track and vertically.
  StageSetup settle;
  settle.stone_friction = c.ballast.friction;
  settle.stone_local_damping = c.preparation.local_damping;
  settle.sleeper = sleeper;
  for (; next + 1 < stages.size(); ++next) {
    settle.sleeper->centre = bed.sleeper_centre;
    report.stages.push_back(stages[next].run(c, settle, control, bed));
    if (!control.quiet) print_remaining(stages, next + 1, report, bed.stones.size(), bed.stones.size());
    if (done(names[next], names[next + 1])) return std::nullopt;
  }

  // Step 6: settle with the design friction, the sleeper free to sink onto the bed.
  settle.sleeper->centre = bed.sleeper_centre;
  const Stage settling = run_stage(c, bed.domain, bed.stones, settle, {"settle", c.preparation.equilibrium_ratio,
                                   c.preparation.max_settling_time, bed.mean_size,
                                   RestCriterion::kForcesAndEnergy}, control.quiet, control.stage_directory);
  report.stages.push_back(settling.report);

  Packing p;
  p.config = c;
  p.stones = std::move(bed.records);
  p.bodies = body_states(settling.sim);
  p.sleeper = settling.sim.boxes()[0];
  p.sleeper.velocity = dem::Vec3::Zero();
  p.domain = bed.domain;
  // Every stage starts its clock at zero: the preparation lasted the sum of the stages' times.
  p.preparation_time = 0.0;
  for (std::size_t k = first_stage; k < report.stages.size(); ++k) p.preparation_time += report.stages[k].simulated_time;
  p.unbalanced_force_ratio = settling.sim.unbalanced_force_ratio();
  p.springs = settling.sim.contact_springs();
  return p;
}

Packing prepare_bed(const PushStudyConfig& c, bool quiet, PreparationReport& report,
                    const std::filesystem::path& stage_directory) {
  PreparationControl control;
  control.quiet = quiet;
  control.stage_directory = stage_directory;
  return *prepare_bed(c, control, report);
}

}  // namespace mfdem::railway
