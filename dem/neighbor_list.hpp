#pragma once
// Verlet neighbour list built with a cell list.
//
// Holds every pair of elements of different bodies closer than Ra + Rb + skin, once (i < j),
// grouped by i in increasing order (CSR). The list stays valid until some element has moved
// more than skin/2 since the build (the displacement criterion), so contacts are never missed.
// Periodic images: a pair stores the integer image of j (in box lengths) that is closest to i.
#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "dem/bodies.hpp"
#include "dem/domain.hpp"

namespace mfdem::dem {

using Image = std::array<std::int8_t, 3>;

struct PairList {
  std::vector<Index> first;   // pairs [i, then j...] of element i: [row_start[i], row_start[i+1])
  std::vector<Index> second;
  std::vector<Image> image;
  std::vector<Index> row_start;
  // For each element e, the pairs in which it is the second member (gather without races).
  std::vector<Index> as_second_start;
  std::vector<Index> as_second_pair;

  Index size() const { return static_cast<Index>(first.size()); }
};

inline Vec3 image_shift(const Image& image, const Vec3& box_length) {
  return Vec3(image[0] * box_length[0], image[1] * box_length[1], image[2] * box_length[2]);
}

// A periodic length must hold this many largest contact reaches (2 x largest radius + skin): then
// at most one image of an element is within reach of another.
inline constexpr double kPeriodicReaches = 2.0;
// The shortest periodic length the search accepts for elements up to `largest_radius`, m.
inline double shortest_periodic_length(double largest_radius, double skin) {
  return kPeriodicReaches * (2.0 * largest_radius + skin);
}

// A periodic axis shorter than shortest_periodic_length: the domain's fault, named by axis.
class PeriodicBoxTooShortError : public std::invalid_argument {
 public:
  PeriodicBoxTooShortError(int axis, double length, double shortest);
  int axis;
  double length, shortest;  // m
};

// Cell-list search; deterministic: the result does not depend on the number of threads.
PairList build_pair_list(const Elements& elements, const Domain& domain, double skin);
// O(N^2) reference search for tests; same pairs, in (i, j) order.
PairList brute_force_pair_list(const Elements& elements, const Domain& domain, double skin);

}  // namespace mfdem::dem
