#pragma once
// Rigid plane walls. A wall is the half-space boundary {x : (x - point).normal = 0}; bodies
// live on the side the normal points to. Walls move at a prescribed velocity and record the
// total force the elements exert on them.
#include <string>
#include <vector>

#include "dem/types.hpp"

namespace mfdem::dem {

struct PlaneWall {
  std::string name;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();    // unit, into the domain
  Vec3 velocity = Vec3::Zero();   // prescribed, m/s
  int material = 0;
};

// The five or six inward-facing planes of an axis-aligned box [min, max].
std::vector<PlaneWall> box_walls(const std::string& name, const Vec3& min, const Vec3& max,
                                 bool open_top, int material);

}  // namespace mfdem::dem
