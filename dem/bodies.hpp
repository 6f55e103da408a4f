#pragma once
// Particle data, structure of arrays.
//
// A body is a rigid object that moves (a sphere or, later, a clump of pebbles); an element is
// one sphere of surface geometry and points to its body. A plain sphere is a body with one
// element at its centre. Turning a clump into a ball is therefore a change of data, not of
// types.
#include <vector>

#include "dem/types.hpp"

namespace mfdem::dem {

struct Bodies {
  std::vector<Vec3> position;          // centre of mass, m
  std::vector<Vec3> velocity;          // m/s
  std::vector<Vec3> angular_velocity;  // world frame, rad/s
  std::vector<Quat> orientation;       // body (principal) frame to world
  std::vector<double> mass;            // kg
  std::vector<Vec3> inertia;           // principal moments, kg m^2
  std::vector<double> local_damping;   // alpha of PFC-style local damping, -
  std::vector<Vec3> force;             // total force of the last evaluation, N
  std::vector<Vec3> unbalanced_force;  // the same before local damping: what equilibrium tests read
  std::vector<Vec3> torque;            // total torque, world frame, N m
  std::vector<Index> first_element;    // elements of body b: [first_element[b], first_element[b+1])

  Index size() const { return static_cast<Index>(position.size()); }
  Index element_begin(Index b) const { return first_element[b]; }
  Index element_end(Index b) const { return first_element[b + 1]; }
};

struct Elements {
  std::vector<Vec3> position;  // world, m (derived from the body each step)
  std::vector<Vec3> offset;    // from the body's centre, body frame, m
  std::vector<double> radius;  // m
  std::vector<int> material;   // index into the MaterialTable
  std::vector<Index> body;

  Index size() const { return static_cast<Index>(position.size()); }
};

}  // namespace mfdem::dem
