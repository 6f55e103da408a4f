#include "fidelity/stone_bodies.hpp"

#include <algorithm>

namespace mfdem::fidelity {

dem::ClumpSpec stone_as_clump(const ClumpTemplate& shape, const StoneDraw& draw, double density,
                              int material, const dem::Vec3& centre) {
  dem::ClumpSpec c;
  c.position = centre;
  c.orientation = draw.orientation;
  c.mass = shape.mass(density, draw.size);
  c.principal_inertia = shape.inertia(density, draw.size);
  for (const auto& p : shape.pebbles_at(draw.size)) c.pebbles.push_back({p.centre, p.radius});
  c.material = material;
  return c;
}

dem::SphereSpec stone_as_ball(const ClumpTemplate& shape, const StoneDraw& draw, int material,
                              const dem::Vec3& centre) {
  dem::SphereSpec s;
  s.position = centre;
  s.radius = shape.equivalent_radius(draw.size);
  s.material = material;
  return s;
}

double template_reach(const ClumpTemplate& shape) {
  double reach = 0.0;
  for (const auto& p : shape.pebbles) reach = std::max(reach, p.centre.norm() + p.radius);
  return reach;
}

}  // namespace mfdem::fidelity
