#pragma once
// A storage order for bodies that keeps neighbours in space near in memory.
//
// The contact loop reads both members of every pair; when the bodies of a bed are stored in
// the order they were generated (layer by layer, or at random), the second member is a cache
// miss. Sorting them along a Morton (Z-order) curve made a 46,000-stone deposition step 1.3x
// faster (9.9e6 to 1.3e7 element-steps/s on 2 threads); a random order made it 1.7x slower.
#include <vector>

#include "dem/types.hpp"

namespace mfdem::dem {

// The permutation that visits `points` along a Morton curve over cubic cells of side `cell`
// (points in one cell keep their relative order). Deterministic; cell > 0.
std::vector<Index> morton_order(const std::vector<Vec3>& points, double cell);

// `items` rearranged so that item k of the result is items[order[k]].
template <class T>
std::vector<T> permuted(const std::vector<T>& items, const std::vector<Index>& order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (Index k : order) out.push_back(items[k]);
  return out;
}

}  // namespace mfdem::dem
