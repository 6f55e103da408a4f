#pragma once
// The simulation box: bounds for neighbour search and optional periodic axes.
#include <array>
#include <cmath>

#include "dem/types.hpp"

namespace mfdem::dem {

struct Domain {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Ones();
  std::array<bool, 3> periodic = {false, false, false};

  Vec3 length() const { return max - min; }

  // Wraps a point into [min, max) along periodic axes; returns the shift applied.
  Vec3 wrap_shift(const Vec3& x) const {
    Vec3 shift = Vec3::Zero();
    for (int a = 0; a < 3; ++a) {
      if (!periodic[a]) continue;
      const double l = max[a] - min[a];
      shift[a] = -std::floor((x[a] - min[a]) / l) * l;
    }
    return shift;
  }

  // The periodic image of a separation d nearest zero (minimum image along periodic axes).
  Vec3 nearest_image(Vec3 d) const {
    for (int a = 0; a < 3; ++a) {
      if (!periodic[a]) continue;
      const double l = max[a] - min[a];
      d[a] -= l * std::round(d[a] / l);
    }
    return d;
  }
};

}  // namespace mfdem::dem
