// Bubble packing: pebbles stay inside the stone, and the clump's error against the stone's
// surface falls as the resolution (number of pebbles) grows.
#include <catch2/catch.hpp>

#include <cmath>

#include "fidelity/bubble_pack.hpp"
#include "fidelity/clump_template.hpp"
#include "fidelity/stone_generator.hpp"

using namespace mfdem::fidelity;

namespace {

const StoneSpec stone_spec{"pack", 1004, 1.55, 0.6, 14};
constexpr int grid = 32;  // coarser than the library's 40, to keep the test quick

ClumpTemplate inscribed_clump(const TriangleMesh& stone, int pebbles, BubblePackRule rule) {
  const auto packed = bubble_pack(stone, {.pebbles = pebbles, .grid_cells = grid, .rule = rule});
  ClumpTemplate clump = clump_from_pebbles("pack", packed);
  fit_to_surface(clump, stone);
  return clump;
}

}  // namespace

TEST_CASE("bubble-packed pebbles lie inside the surface and touch it", "[fidelity][pack]") {
  const TriangleMesh stone = generate_stone(stone_spec);
  const auto pebbles = bubble_pack(stone, {.pebbles = 12, .grid_cells = grid});
  REQUIRE(pebbles.size() == 12);
  for (const auto& p : pebbles) {
    CHECK(inside(stone, p.centre));
    CHECK(p.radius == Approx(distance_to_surface(stone, p.centre)).epsilon(1e-12));  // largest sphere there
  }
  // Greedy and deterministic: fewer pebbles are the first of more.
  const auto fewer = bubble_pack(stone, {.pebbles = 5, .grid_cells = grid});
  for (std::size_t i = 0; i < fewer.size(); ++i) CHECK(fewer[i].centre == pebbles[i].centre);
}

TEST_CASE("the volume and inertia errors of inscribed pebbles fall as pebbles are added", "[fidelity][pack]") {
  const TriangleMesh stone = generate_stone(stone_spec);
  for (auto rule : {BubblePackRule::largest_new_volume, BubblePackRule::farthest_point}) {
    CAPTURE(static_cast<int>(rule));
    double previous_volume_error = 1.0, previous_inertia_error = 1.0;
    for (int pebbles : {2, 6, 24}) {
      CAPTURE(pebbles);
      const ClumpTemplate clump = inscribed_clump(stone, pebbles, rule);
      const double volume_error = -clump.fit->volume_error;  // inscribed: always smaller than the stone
      CHECK(volume_error > 0.0);
      CHECK(volume_error < previous_volume_error);
      CHECK(clump.fit->inertia_error < previous_inertia_error);
      CHECK(clump.fit->protrusion < 1e-12);
      previous_volume_error = volume_error;
      previous_inertia_error = clump.fit->inertia_error;
    }
  }
}

TEST_CASE("largest_new_volume covers more of the stone than farthest_point", "[fidelity][pack]") {
  const TriangleMesh stone = generate_stone(stone_spec);
  for (int pebbles : {4, 12}) {
    CHECK(inscribed_clump(stone, pebbles, BubblePackRule::largest_new_volume).volume >
          inscribed_clump(stone, pebbles, BubblePackRule::farthest_point).volume);
  }
}

TEST_CASE("matching the volume gives the stone's volume, and the inertia error falls with pebbles", "[fidelity][pack]") {
  const TriangleMesh stone = generate_stone(stone_spec);
  const double stone_volume = mesh_mass_properties(stone).volume;
  double previous_inertia_error = 1.0;
  for (int pebbles : {2, 24}) {
    auto packed = bubble_pack(stone, {.pebbles = pebbles, .grid_cells = grid});
    const double factor = radius_factor_for_volume(packed, stone_volume);
    CHECK(factor > 1.0);
    for (auto& p : packed) p.radius *= factor;
    ClumpTemplate clump = clump_from_pebbles("matched", packed);
    fit_to_surface(clump, stone);
    // Secant tolerance 1e-5 plus the fixed-point integration's own ~1e-5.
    CHECK(std::abs(clump.fit->volume_error) < 1e-4);
    CHECK(clump.fit->inertia_error < previous_inertia_error);
    CHECK(clump.fit->inertia_error < inscribed_clump(stone, pebbles, BubblePackRule::largest_new_volume).fit->inertia_error);
    previous_inertia_error = clump.fit->inertia_error;
  }
}

TEST_CASE("the smallest-radius knob stops the packing", "[fidelity][pack]") {
  const TriangleMesh stone = generate_stone(stone_spec);
  const auto pebbles = bubble_pack(stone, {.pebbles = 1000, .min_radius = 0.2, .grid_cells = grid});
  REQUIRE_FALSE(pebbles.empty());
  CHECK(pebbles.size() < 1000);
  for (const auto& p : pebbles) CHECK(p.radius >= 0.2);
  CHECK_THROWS_WITH(bubble_pack(stone, {.pebbles = 0}), Catch::Contains("at least one pebble"));
}
