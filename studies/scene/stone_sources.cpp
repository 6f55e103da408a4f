#include "studies/scene/stone_sources.hpp"

#include <fmt/format.h>
#include <gsl/gsl_rng.h>

#include <cmath>
#include <memory>

#include "fidelity/grading.hpp"
#include "fidelity/shape_library.hpp"
#include "fidelity/stone_bodies.hpp"
#include "studies/scene/sphere_sources.hpp"

namespace mfdem::scene {
namespace {

dem::Vec3 to_vec(const std::array<double, 3>& a) { return dem::Vec3(a[0], a[1], a[2]); }

}  // namespace

StoneBodies generate_stone_group(const config::Section& s, const dem::MaterialTable& materials,
                                 std::uint64_t seed, std::int64_t first_stone) {
  const dem::Vec3 lo = to_vec(s.vec3("min", "region corner in m"));
  const dem::Vec3 hi = to_vec(s.vec3("max", "region corner in m"));
  const long long count = s.integer("count", {.min = 1}, "number of stones");
  const int material = material_key(s, materials);
  const fidelity::Representation representation =
      fidelity::representation_named(s.choice("representation", {"clump", "ball"}, "clump"));
  const double fixed_size = s.number_or("size", 0.0, {.min = 0.0}, "sieve size in m (0: graded)");
  const dem::Vec3 velocity = to_vec(s.vec3_or("velocity", {0, 0, 0}, "velocity in m/s"));
  const double random_speed = s.number_or("random_speed", 0.0, {.min = 0.0}, "random speed in m/s");
  fidelity::ShapeLibrary custom;
  const fidelity::ShapeLibrary* library = &fidelity::standard_library();
  if (s.has("library")) {
    try {
      custom = fidelity::load_library(s.text("library"));
    } catch (const std::exception& e) {
      s.fail("library", fmt::format("a directory of clump templates ({})", e.what()));
    }
    library = &custom;
  }
  const auto& templates = library->templates;
  const fidelity::StoneSampler sampler(seed, static_cast<int>(templates.size()));

  std::vector<fidelity::StoneDraw> draws(count);
  double reach = 0.0;
  for (long long k = 0; k < count; ++k) {
    draws[k] = sampler.draw(first_stone + k);
    if (fixed_size > 0.0) draws[k].size = fixed_size;
    const auto& shape = templates[draws[k].template_index];
    reach = std::max(reach, representation == fidelity::Representation::ball ? shape.equivalent_radius(draws[k].size)
                                                     : fidelity::template_reach(shape) * draws[k].size);
  }
  const double pitch = 2.0 * reach * 1.02;  // no two stones overlap at the start
  const auto centres = lattice_centres(s, lo, hi, pitch, count, "stones");
  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed + 7919 * (first_stone + 1)));
  const double density = materials[material].density;
  StoneBodies out;
  for (long long k = 0; k < count; ++k) {
    const dem::Vec3& centre = centres[k];
    const dem::Vec3 jitter(gsl_rng_uniform(rng.get()) - 0.5, gsl_rng_uniform(rng.get()) - 0.5,
                           gsl_rng_uniform(rng.get()) - 0.5);
    const auto& shape = templates[draws[k].template_index];
    if (representation == fidelity::Representation::clump) {
      auto c = fidelity::stone_as_clump(shape, draws[k], density, material, centre);
      c.velocity = velocity + 2.0 * random_speed * jitter;
      out.clumps.push_back(std::move(c));
    } else {
      auto b = fidelity::stone_as_ball(shape, draws[k], material, centre);
      b.velocity = velocity + 2.0 * random_speed * jitter;
      out.balls.push_back(b);
    }
  }
  return out;
}

}  // namespace mfdem::scene
