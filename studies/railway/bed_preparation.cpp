#include "studies/railway/bed_preparation.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "dem/spatial_order.hpp"
#include "fidelity/conversion.hpp"
#include "studies/railway/ball_growth.hpp"
#include "studies/railway/compaction_stages.hpp"
#include "studies/railway/preparation_stage.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stone_columns.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

bool intersects_box(const dem::ClumpSpec& stone, const dem::RigidBox& box) {
  for (const auto& p : stone.pebbles) {
    const dem::Vec3 x = stone.position + stone.orientation.normalized() * p.offset;
    if (dem::sphere_box_contact(x, p.radius, box.centre, box.half_extent)) return true;
  }
  return false;
}

double highest_point(const std::vector<dem::ClumpSpec>& bodies) {
  double top = 0.0;
  for (const auto& b : bodies)
    for (const auto& p : b.pebbles) top = std::max(top, b.position.z() + p.offset.norm() + p.radius);
  return top;
}

std::vector<dem::Vec3> positions_of(const std::vector<dem::ClumpSpec>& bodies) {
  std::vector<dem::Vec3> x;
  for (const auto& b : bodies) x.push_back(b.position);
  return x;
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

// The alternative conversion point: the deposited bed converted and its balls grown in the
// deposition's container, with its friction and damping.
void convert_deposited(const PushStudyConfig& c, const fidelity::Policy& policy, bool quiet, BedBetweenStages& bed,
                       PreparationReport& report) {
  const fidelity::BedFrame frame{0.0, sleeper_box(c.geometry), bed.domain};
  const fidelity::ConvertedBed converted = fidelity::convert_bed(bed.stones, {}, policy, frame, c.ballast.density, kBall);
  check_balls_fit(c, converted);
  const GrownBed grown = grow_balls(c, bed.domain, converted, deposition_setup(c));
  bed.stones = grown.bodies;
  StageReport stage = grown.report;
  stage.name = "convert";
  report.stages.push_back(stage);
  if (!quiet)
    fmt::print(stderr, "convert: {} of {} deposited stones made balls by {} ({} reshaped, grown from {:.2f} (smallest) / "
               "{:.2f} (mean) of their radius in {})\n", converted.converted, bed.stones.size(), policy.describe(),
               grown.reshaped, grown.smallest_start_fraction, grown.mean_start_fraction,
               scene::format_duration(stage.wall_seconds));
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
  if (p.expansion_strain > 0.0) stages.push_back({"expand", p.expansion_time, run_expansion});
  if (p.tamping_depth > 0.0) stages.push_back({"tamp", p.tamping_time, run_tamping});
  if (p.consolidation_gravity > 1.0) stages.push_back({"consolidate", p.consolidation_time, run_consolidation});
  if (p.traffic_cycles > 0) stages.push_back({"traffic", p.traffic_cycles * p.traffic_period, run_traffic});
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

// Appends a stage's report; a continued packing repeats stages, whose reports are then named
// NAME_2, NAME_3, ... (a packing file keeps each under its name).
void add_report(PreparationReport& report, StageReport stage) {
  const auto taken = [&](const std::string& name) {
    return std::any_of(report.stages.begin(), report.stages.end(), [&](const StageReport& s) { return s.name == name; });
  };
  const std::string base = stage.name;
  for (int k = 2; taken(stage.name); ++k) stage.name = fmt::format("{}_{}", base, k);
  report.stages.push_back(std::move(stage));
}

}  // namespace

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
  if (!control.continue_from.empty()) {
    next = static_cast<std::size_t>(std::find(names.begin(), names.end(), "traffic") - names.begin());
    if (next == names.size())
      throw std::invalid_argument(fmt::format("--continue-from {}: this config runs no traffic (traffic_cycles = {}); "
                                              "set [preparation] traffic_cycles to the pulses to add",
                                              control.continue_from.string(), c.preparation.traffic_cycles));
    if (!control.stop_after.empty() && stop_index <= next)
      throw std::invalid_argument(fmt::format("--stop-after {}: done before the packing {} was finished",
                                              control.stop_after, control.continue_from.string()));
    bed = load_finished_bed(control.continue_from, c, report);
    if (control.before_work) control.before_work();
    report.continued_from = control.continue_from.string();
    if (!control.quiet)
      fmt::print(stderr, "continuing {}: {} stones, {} more traffic pulses, then settling\n",
                 control.continue_from.string(), bed.stones.size(), c.preparation.traffic_cycles);
  } else if (control.resume || reuse) {
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
    if (control.before_work) control.before_work();
    if (!control.quiet)
      fmt::print(stderr, "{} {}: {} stones, next stage '{}'\n", reuse ? "deposited bed from" : "resuming from",
                 from.string(), bed.stones.size(), name);
  } else {
    if (control.before_work) control.before_work();
    bed = deposit(c, control.quiet, report, control.stage_directory);
    if (done("deposit", names.front())) return std::nullopt;
  }
  // A bed past its trimming (resumed from a later checkpoint) was converted before it was saved.
  if (control.convert_after_deposit && !bed.trimmed)
    convert_deposited(c, *control.convert_after_deposit, control.quiet, bed, report);
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
    add_report(report, stages[next].run(c, settle, control, bed));
    if (!control.quiet) print_remaining(stages, next + 1, report, bed.stones.size(), bed.stones.size());
    if (done(names[next], names[next + 1])) return std::nullopt;
  }

  // Step 6: settle with the design friction, the sleeper free to sink onto the bed.
  settle.sleeper->centre = bed.sleeper_centre;
  const Stage settling = run_stage(c, bed.domain, bed.stones, settle, {"settle", c.preparation.equilibrium_ratio,
                                   c.preparation.max_settling_time, bed.mean_size,
                                   RestCriterion::kForcesAndEnergy, settling_creep(c, bed.mean_size)},
                                   control.quiet, control.stage_directory);
  add_report(report, settling.report);

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
  p.continued_from = report.continued_from;
  if (control.convert_after_deposit) {
    p.model = control.convert_after_deposit->describe();
    p.conversion_point = "after deposition";
  }
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
