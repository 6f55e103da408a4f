// Morton storage order (dem/spatial_order.hpp). Reference: the Z-order curve visits the eight
// cells of every 2 x 2 x 2 block one after the other, x fastest, and the blocks themselves in Z
// order; points in one cell keep their input order.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include "dem/spatial_order.hpp"

using mfdem::dem::Index;
using mfdem::dem::Vec3;

TEST_CASE("the Morton order visits a shuffled 4x4x4 lattice block by block", "[dem][order]") {
  std::vector<Vec3> lattice;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) lattice.emplace_back(0.05 * x + 0.01, 0.05 * y + 0.01, 0.05 * z + 0.01);
  std::vector<Vec3> shuffled = lattice;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
  const std::vector<Index> order = mfdem::dem::morton_order(shuffled, 0.05);
  const std::vector<Vec3> sorted = mfdem::dem::permuted(shuffled, order);
  REQUIRE(sorted.size() == 64);
  // Every run of eight is one 2 x 2 x 2 block, and inside it x changes fastest, then y, then z.
  for (int block = 0; block < 8; ++block) {
    const Vec3 corner = sorted[8 * block];
    for (int k = 0; k < 8; ++k) {
      const Vec3 expected = corner + 0.05 * Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
      CHECK((sorted[8 * block + k] - expected).norm() < 1e-12);
    }
  }
  // The blocks in Z order: block b's corner is at 0.1 x (b & 1, b >> 1 & 1, b >> 2 & 1).
  for (int block = 0; block < 8; ++block) {
    const Vec3 expected = Vec3(0.01, 0.01, 0.01) + 0.1 * Vec3(block & 1, (block >> 1) & 1, (block >> 2) & 1);
    CHECK((sorted[8 * block] - expected).norm() < 1e-12);
  }
}

TEST_CASE("the Morton order is a permutation that keeps points of one cell in input order", "[dem][order]") {
  const std::vector<Vec3> points = {Vec3(0.31, 0, 0), Vec3(0.01, 0, 0), Vec3(0.32, 0, 0), Vec3(0.02, 0, 0)};
  const std::vector<Index> order = mfdem::dem::morton_order(points, 0.1);
  CHECK(order == std::vector<Index>{1, 3, 0, 2});
  CHECK_THROWS_WITH(mfdem::dem::morton_order(points, 0.0), Catch::Matchers::Contains("cell size must be > 0"));
}
