#pragma once
// [[stone_group]]: ballast stones from the shape library, sized by a sieve curve, placed on a
// lattice in a region, each as a clump or as its equal-volume ball.
#include <cstdint>

#include "dem/simulation.hpp"
#include "studies/config/config.hpp"

namespace mfdem::scene {

struct StoneBodies {
  std::vector<dem::ClumpSpec> clumps;
  std::vector<dem::SphereSpec> balls;
};

// Keys: min, max (region, m), count, material, representation = "clump" | "ball",
// library (directory; default: the shipped 6-pebble library), size (m; fixed sieve size
// instead of the EN 13450 31.5/63 curve), random_speed (m/s), velocity (m/s).
// `first_stone` numbers the stones across groups so every stone has its own random stream.
StoneBodies generate_stone_group(const config::Section& s, const dem::MaterialTable& materials,
                                 std::uint64_t seed, std::int64_t first_stone);

}  // namespace mfdem::scene
