#include "studies/railway/bed_preparation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "studies/railway/section_simulation.hpp"
#include "studies/railway/stone_columns.hpp"

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

dem::RigidBox sleeper_box(const SectionGeometry& g) {
  dem::RigidBox box;
  box.name = "sleeper";
  box.half_extent = 0.5 * dem::Vec3(g.sleeper_length, g.sleeper_width, g.sleeper_height);
  box.centre = dem::Vec3(0.0, 0.5 * g.section_length, g.sleeper_base() + 0.5 * g.sleeper_height);
  box.mass = g.sleeper_mass;
  box.material = kSleeper;
  box.velocity = dem::Vec3::Zero();
  box.driven = {true, true, false};  // held across and along the track, free to settle
  return box;
}

// The work of lifting the stones by one mean stone size, J: the energy scale of "at rest".
double lifting_energy(const std::vector<dem::ClumpSpec>& stones, double mean_size, const PushStudyConfig&) {
  double mass = 0.0;
  for (const auto& s : stones) mass += s.mass;
  return mass * kGravity * mean_size;
}

double highest_point(const std::vector<dem::ClumpSpec>& bodies) {
  double top = 0.0;
  for (const auto& b : bodies)
    for (const auto& p : b.pebbles) top = std::max(top, b.position.z() + p.offset.norm() + p.radius);
  return top;
}

}  // namespace

Packing prepare_bed(const PushStudyConfig& c, bool quiet, PreparationReport& report,
                    const std::filesystem::path& stage_directory) {
  const auto stage_file = [&](const dem::Simulation& sim, const char* name) {
    return stage_directory.empty() ? nullptr
                                   : std::make_unique<dem::StateFile>(stage_directory / (std::string(name) + ".h5"), sim, name);
  };
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
  drawn = place_in_columns(c, std::move(drawn));
  double mean_size = 0.0;
  for (const auto& s : drawn) mean_size += s.record.size / static_cast<double>(count);
  report.stones_generated = count;

  std::vector<dem::ClumpSpec> bodies;
  for (const auto& s : drawn) bodies.push_back(s.body);
  const dem::Domain domain = section_domain(c, highest_point(bodies) + 0.1);

  // Step 3: deposition with lowered friction inside the container.
  StageSetup deposit;
  deposit.stone_friction = c.preparation.deposition_friction;
  deposit.stone_local_damping = c.preparation.deposition_local_damping;
  deposit.container_walls = true;
  dem::Simulation deposition = make_section_simulation(c, domain, bodies, deposit);
  deposition.prepare();
  report.time_step = deposition.time_step();
  if (!quiet)
    fmt::print(stderr, "deposition: {} stones, {} elements, time step {:.3g} s (limit {:.3g} s: {})\n", count,
               deposition.elements().size(), deposition.time_step(), deposition.time_step_limit().limit,
               deposition.time_step_limit().reason);
  auto deposition_frames = stage_file(deposition, "deposit");
  report.stages.push_back(run_until_settled(deposition, "deposit", c.preparation.deposition_ratio,
                                            lifting_energy(bodies, mean_size, c),
                                            c.preparation.max_deposition_time, quiet,
                                            deposition_frames.get()));

  // Step 4: trim to the profile, cut the sleeper's place, put the sleeper in.
  const dem::RigidBox sleeper = sleeper_box(g);
  const auto deposited = body_states(deposition);
  std::vector<dem::ClumpSpec> kept;
  std::vector<StoneRecord> records;
  for (std::size_t k = 0; k < deposited.size(); ++k) {
    const dem::ClumpSpec& s = deposited[k];
    if (s.position.z() > g.surface_height(s.position.x())) continue;
    if (intersects_box(s, sleeper)) continue;
    kept.push_back(s);
    records.push_back(drawn[k].record);
  }
  report.stones_removed = count - static_cast<std::int64_t>(kept.size());

  // Step 5: settle with the design friction, the sleeper free to sink onto the bed.
  StageSetup settle;
  settle.stone_friction = c.ballast.friction;
  settle.stone_local_damping = c.preparation.local_damping;
  settle.sleeper = sleeper;
  dem::Simulation settling = make_section_simulation(c, domain, kept, settle);
  settling.prepare();
  auto settling_frames = stage_file(settling, "settle");
  report.stages.push_back(run_until_settled(settling, "settle", c.preparation.equilibrium_ratio,
                                            lifting_energy(kept, mean_size, c),
                                            c.preparation.max_settling_time, quiet,
                                            settling_frames.get()));

  Packing p;
  p.config = c;
  p.stones = std::move(records);
  p.bodies = body_states(settling);
  p.sleeper = settling.boxes()[0];
  p.sleeper.velocity = dem::Vec3::Zero();
  p.domain = domain;
  p.preparation_time = deposition.time() + settling.time();
  p.unbalanced_force_ratio = settling.unbalanced_force_ratio();
  return p;
}

}  // namespace mfdem::railway
