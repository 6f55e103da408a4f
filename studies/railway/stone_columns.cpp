#include "studies/railway/stone_columns.hpp"

#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "fidelity/stone_bodies.hpp"
#include "studies/railway/section_simulation.hpp"

namespace mfdem::railway {
namespace {

constexpr double kUpperSizePassing = 97.0;  // % passing at the upper sieve size D

}  // namespace

StoneFactory::StoneFactory(const PushStudyConfig& c)
    : config_(c),
      library_(c.stones.library.empty() ? fidelity::standard_library() : fidelity::load_library(c.stones.library)),
      sampler_(c.seed, static_cast<int>(library_.templates.size())) {}

DrawnStone StoneFactory::draw(std::int64_t k) const {
  fidelity::StoneDraw d = sampler_.draw(k);
  if (config_.stones.fixed_size > 0.0) d.size = config_.stones.fixed_size;
  const auto& shape = library_.templates[d.template_index];
  DrawnStone s;
  s.record = {k, d.template_index, d.size};
  if (config_.stones.representation == fidelity::Representation::clump) {
    s.body = fidelity::stone_as_clump(shape, d, config_.ballast.density, kBallast, dem::Vec3::Zero());
    s.reach = fidelity::template_reach(shape) * d.size;
  } else {
    s.body = dem::sphere_body(fidelity::stone_as_ball(shape, d, kBall, dem::Vec3::Zero()), config_.ballast.density);
    s.reach = shape.equivalent_radius(d.size);
  }
  return s;
}

double StoneFactory::upper_size() const {
  if (config_.stones.fixed_size > 0.0) return config_.stones.fixed_size;
  for (const auto& p : sampler_.curve().points())
    if (p.passing_percent >= kUpperSizePassing) return p.size_mm * 1e-3;
  return sampler_.curve().largest_mm() * 1e-3;
}

double StoneFactory::mean_volume(int sample) const {
  double sum = 0.0;
  for (int k = 0; k < sample; ++k) sum += draw(k).body.mass / config_.ballast.density;
  return sum / sample;
}

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
    std::vector<dem::Pebble> pebbles;  // offsets turned into the world frame
  };
  std::vector<std::vector<Placed>> columns(static_cast<std::size_t>(nx) * ny);
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(c.seed % 4294967291ULL) + 1);
  const dem::Domain period = section_domain(c, 1.0);  // only its periodic y matters here
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
    Placed placed{dem::Vec3::Zero(), s.reach, s.body.pebbles};
    double z = 0.0;  // the lowest height at which every pebble clears the floor
    for (auto& p : placed.pebbles) {
      p.offset = s.body.orientation * p.offset;
      z = std::max(z, p.radius - p.offset.z() + gap);
    }
    // Dropped straight down onto the stones below: it rests where one of its pebbles first
    // meets a pebble under it. Stacking by bounding spheres left columns 1.6x taller, and the
    // fall took half the deposition.
    for (int di = -2; di <= 2; ++di)
      for (int dj = -2; dj <= 2; ++dj) {
        const int ii = i + di;
        int jj = j + dj;
        if (ii < 0 || ii >= nx) continue;
        if (g.periodic_along_track) jj = (jj % ny + ny) % ny;
        else if (jj < 0 || jj >= ny) continue;
        for (const Placed& o : columns[static_cast<std::size_t>(jj) * nx + ii]) {
          const double reach = s.reach + o.reach + gap;
          if (o.x.z() + reach <= z) continue;  // cannot lift it above where it already is
          const dem::Vec3 e = period.nearest_image(dem::Vec3(x, y, 0.0) - dem::Vec3(o.x.x(), o.x.y(), 0.0));
          if (e.squaredNorm() >= reach * reach) continue;
          for (const dem::Pebble& a : placed.pebbles)
            for (const dem::Pebble& b : o.pebbles) {
              const double ex = e.x() + a.offset.x() - b.offset.x(), ey = e.y() + a.offset.y() - b.offset.y();
              const double touch = a.radius + b.radius + gap;
              const double flat2 = ex * ex + ey * ey;
              if (flat2 >= touch * touch) continue;
              z = std::max(z, o.x.z() + b.offset.z() + std::sqrt(touch * touch - flat2) - a.offset.z());
            }
        }
      }
    s.body.position = dem::Vec3(x, y, z);
    placed.x = s.body.position;
    columns[column].push_back(std::move(placed));
  }
  // A uniform collapse: each stone starts down at a speed proportional to its height, so the
  // columns close up together instead of the top stones falling longest.
  double top = 0.0;
  for (const auto& s : stones) top = std::max(top, s.body.position.z());
  for (auto& s : stones) s.body.velocity = dem::Vec3(0.0, 0.0, -c.preparation.drop_speed * s.body.position.z() / top);
  return stones;
}

}  // namespace mfdem::railway
