#include "studies/railway/bed_preparation.hpp"

#include <fmt/format.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "fidelity/grading.hpp"
#include "fidelity/shape_library.hpp"
#include "fidelity/stone_bodies.hpp"
#include "studies/railway/section_simulation.hpp"

namespace mfdem::railway {
namespace {

constexpr double kGravity = 9.81;          // m/s^2, the solver's default gravity
constexpr double kUpperSizePassing = 97.0;  // % passing at the upper sieve size D

struct DrawnStone {
  StoneRecord record;
  dem::ClumpSpec body;  // at the origin
  double reach = 0.0;   // bounding radius about the centre of mass, m
};

class StoneFactory {
 public:
  explicit StoneFactory(const PushStudyConfig& c)
      : config_(c),
        library_(c.stones.library.empty() ? fidelity::standard_library() : fidelity::load_library(c.stones.library)),
        sampler_(c.seed, static_cast<int>(library_.templates.size())) {}

  DrawnStone draw(std::int64_t k) const {
    fidelity::StoneDraw d = sampler_.draw(k);
    if (config_.stones.fixed_size > 0.0) d.size = config_.stones.fixed_size;
    const auto& shape = library_.templates[d.template_index];
    DrawnStone s;
    s.record = {k, d.template_index, d.size};
    if (config_.stones.representation == "clump") {
      s.body = fidelity::stone_as_clump(shape, d, config_.ballast.density, kBallast, dem::Vec3::Zero());
      s.reach = fidelity::template_reach(shape) * d.size;
    } else {
      s.body = dem::sphere_body(fidelity::stone_as_ball(shape, d, kBallast, dem::Vec3::Zero()), config_.ballast.density);
      s.reach = shape.equivalent_radius(d.size);
    }
    return s;
  }

  // The upper size D of the grading (63 mm for 31.5/63 ballast): the smallest sieve that passes
  // at least 97 % by mass, as EN 13450 grades; the fixed size when there is one. The geometry
  // checks count stones of this size (the 1-3 % oversize is left out).
  double upper_size() const {
    if (config_.stones.fixed_size > 0.0) return config_.stones.fixed_size;
    for (const auto& p : sampler_.curve().points())
      if (p.passing_percent >= kUpperSizePassing) return p.size_mm * 1e-3;
    return sampler_.curve().largest_mm() * 1e-3;
  }

  // Mean solid volume of a stone, m^3, over the first `sample` draws.
  double mean_volume(int sample) const {
    double sum = 0.0;
    for (int k = 0; k < sample; ++k) sum += draw(k).body.mass / config_.ballast.density;
    return sum / sample;
  }

 private:
  const PushStudyConfig& config_;
  fidelity::ShapeLibrary library_;
  fidelity::StoneSampler sampler_;
};

// Step 2: columns on a grid over the container floor with the mean stone's footprint. Each stone
// goes on top of its column, raised further where its bounding sphere would touch a stone of a
// neighbouring column (large stones overhang their column), so no two stones touch at the start.
std::vector<DrawnStone> place_in_columns(const PushStudyConfig& c, std::vector<DrawnStone> stones) {
  const SectionGeometry& g = c.geometry;
  double mean_reach = 0.0;
  for (const auto& s : stones) mean_reach += s.reach;
  mean_reach /= std::max<std::size_t>(1, stones.size());
  const double pitch = 2.04 * mean_reach;
  const double width = 2.0 * g.toe_half_width(), length = g.section_length;
  const int nx = std::max(1, static_cast<int>(std::floor(width / pitch)));
  const int ny = std::max(1, static_cast<int>(std::floor(length / pitch)));
  const double dx = width / nx, dy = length / ny;
  struct Placed {
    dem::Vec3 x;
    double reach;
  };
  std::vector<std::vector<Placed>> columns(static_cast<std::size_t>(nx) * ny);
  std::vector<double> column_top(columns.size(), 0.0);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(c.seed % 4294967291ULL) + 1);
  const auto separation_y = [&](double a, double b) {
    double d = a - b;
    if (g.periodic_along_track) d -= length * std::round(d / length);
    return d;
  };
  for (std::size_t k = 0; k < stones.size(); ++k) {
    DrawnStone& s = stones[k];
    const std::size_t column = k % columns.size();
    const int i = static_cast<int>(column % nx), j = static_cast<int>(column / nx);
    // A seeded sideways jitter within the room the stone leaves in its cell; never into a wall.
    const double slack_x = std::max(0.0, 0.5 * dx - s.reach), slack_y = std::max(0.0, 0.5 * dy - s.reach);
    double x = -0.5 * width + (i + 0.5) * dx + (2.0 * gsl_rng_uniform(rng.get()) - 1.0) * slack_x;
    double y = (j + 0.5) * dy + (2.0 * gsl_rng_uniform(rng.get()) - 1.0) * slack_y;
    const double clearance = 1.02 * s.reach;
    x = std::clamp(x, -0.5 * width + clearance, 0.5 * width - clearance);
    if (!g.periodic_along_track) y = std::clamp(y, clearance, length - clearance);
    const double gap = 0.02 * s.reach;
    double z = column_top[column] + gap + s.reach;
    for (bool moved = true; moved;) {
      moved = false;
      for (int di = -2; di <= 2; ++di)
        for (int dj = -2; dj <= 2; ++dj) {
          const int ii = i + di;
          int jj = j + dj;
          if (ii < 0 || ii >= nx) continue;
          if (g.periodic_along_track) jj = (jj % ny + ny) % ny;
          else if (jj < 0 || jj >= ny) continue;
          for (const Placed& o : columns[static_cast<std::size_t>(jj) * nx + ii]) {
            const double reach = s.reach + o.reach + gap;
            const double ex = x - o.x.x(), ey = separation_y(y, o.x.y()), ez = z - o.x.z();
            const double flat2 = ex * ex + ey * ey;
            if (flat2 + ez * ez >= reach * reach) continue;
            z = o.x.z() + std::sqrt(std::max(0.0, reach * reach - flat2)) + 1e-9;  // just above it
            moved = true;
          }
        }
    }
    s.body.position = dem::Vec3(x, y, z);
    columns[column].push_back({s.body.position, s.reach});
    column_top[column] = std::max(column_top[column], z + s.reach);
  }
  // A uniform collapse: each stone starts down at a speed proportional to its height, so the
  // columns close up together instead of the top stones falling longest.
  double top = 0.0;
  for (const auto& s : stones) top = std::max(top, s.body.position.z());
  for (auto& s : stones) s.body.velocity = dem::Vec3(0.0, 0.0, -c.preparation.drop_speed * s.body.position.z() / top);
  return stones;
}

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
