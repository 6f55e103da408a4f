#pragma once
// A rigid, axis-aligned box body, such as a sleeper: it never rotates; along each axis it is
// either driven at a prescribed velocity or free (moved by the contact forces and gravity).
// The lateral push test drives a sleeper along x, holds it along y and leaves it free along z
// under its own weight.
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "dem/types.hpp"

namespace mfdem::dem {

struct RigidBox {
  std::string name;
  Vec3 centre = Vec3::Zero();        // m
  Vec3 half_extent = Vec3::Ones();   // m
  double mass = 1.0;                 // kg
  int material = 0;
  Vec3 velocity = Vec3::Zero();      // m/s; the prescribed value on driven axes
  std::array<bool, 3> driven = {true, true, true};
  // m/s: rate of change of each half extent, a prescribed growth (a sleeper tamped into its bed
  // grows into its place); its work on the elements counts as work put in.
  Vec3 growth_rate = Vec3::Zero();
  // N: an external load on the free axes (a wheel load on a sleeper); its work counts as work put in.
  Vec3 applied_force = Vec3::Zero();
};

// Height of the box's bottom face (a sleeper's base), m.
inline double box_bottom(const RigidBox& box) { return box.centre.z() - box.half_extent.z(); }

// The growth part of the velocity of the box surface point nearest x: each face it lies on
// moves outwards at its axis's growth rate (an edge or corner at the sum).
inline Vec3 box_growth_velocity(const RigidBox& box, const Vec3& x) {
  const Vec3 local = x - box.centre;
  Vec3 v = Vec3::Zero();
  for (int a = 0; a < 3; ++a)
    if (std::abs(local[a]) >= box.half_extent[a]) v[a] = std::copysign(box.growth_rate[a], local[a]);
  return v;
}

// Contact of a sphere (centre x, radius r) with a box: overlap d > 0, unit normal from the box
// to the sphere, and the point of the box surface nearest the sphere's centre. A centre inside
// the box is pushed out through the nearest face.
struct BoxContact {
  double overlap = 0.0;
  Vec3 normal = Vec3::UnitZ();
  Vec3 surface_point = Vec3::Zero();
};

inline std::optional<BoxContact> sphere_box_contact(const Vec3& x, double r, const Vec3& centre,
                                                    const Vec3& half) {
  const Vec3 local = x - centre;
  const Vec3 clamped = local.cwiseMax(-half).cwiseMin(half);
  const Vec3 outside = local - clamped;
  const double distance2 = outside.squaredNorm();
  if (distance2 > 0.0) {
    if (distance2 >= r * r) return std::nullopt;
    const double distance = std::sqrt(distance2);
    return BoxContact{r - distance, outside / distance, centre + clamped};
  }
  // Inside: leave through the face with the smallest depth.
  int axis = 0;
  double depth = half[0] - std::abs(local[0]);
  for (int a = 1; a < 3; ++a) {
    const double d = half[a] - std::abs(local[a]);
    if (d < depth) depth = d, axis = a;
  }
  BoxContact c;
  c.normal = Vec3::Zero();
  c.normal[axis] = local[axis] >= 0.0 ? 1.0 : -1.0;
  c.overlap = r + depth;
  c.surface_point = x;
  c.surface_point[axis] = centre[axis] + c.normal[axis] * half[axis];
  return c;
}

// The faces of a box, for splitting the force on it by where it acts (a sleeper's base, sides and
// ends carry its lateral resistance in different ways): 2 x axis, + 1 on the positive side.
enum BoxFace : int { kMinusX = 0, kPlusX, kMinusY, kPlusY, kMinusZ, kPlusZ, kBoxFaces };

// A box's force split by face, all zero (Eigen vectors start uninitialised).
using BoxFaceForces = std::array<Vec3, kBoxFaces>;
inline BoxFaceForces zero_box_faces() {
  BoxFaceForces f;
  f.fill(Vec3::Zero());
  return f;
}

// The face a contact leans on: the axis of the normal's largest component, on its side. An edge
// or corner contact counts to one face only, so the faces' forces add up to the total.
inline BoxFace box_face(const Vec3& normal) {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(normal[a]) > std::abs(normal[axis])) axis = a;
  return static_cast<BoxFace>(2 * axis + (normal[axis] > 0.0 ? 1 : 0));
}

}  // namespace mfdem::dem
