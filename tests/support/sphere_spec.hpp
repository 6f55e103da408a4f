#pragma once
// A sphere for a test scene in one call.
#include "dem/simulation.hpp"

namespace mfdem::test_support {

inline dem::SphereSpec sphere(const dem::Vec3& position, double radius, int material = 0,
                              const dem::Vec3& velocity = dem::Vec3::Zero(),
                              const dem::Vec3& angular_velocity = dem::Vec3::Zero()) {
  dem::SphereSpec s;
  s.position = position;
  s.radius = radius;
  s.material = material;
  s.velocity = velocity;
  s.angular_velocity = angular_velocity;
  return s;
}

}  // namespace mfdem::test_support
