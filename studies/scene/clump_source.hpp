#pragma once
// [[clump]]: one rigid clump placed by hand from its pebbles, for exact set-ups (a dumbbell on a
// floor, a stone against a wall) that a library draw at a random orientation cannot give.
#include "dem/simulation.hpp"
#include "studies/config/config.hpp"

namespace mfdem::scene {

// Keys: material; position (m, where the origin of the pebble offsets goes); optional axis and
// angle (rad): the rotation of the pebble frame into the world, default none; velocity (m/s),
// angular_velocity (rad/s); one [[clump.pebble]] per sphere with offset (m) and radius (m), at
// least one. Mass, centre of mass and inertia are those of the union of the pebbles (overlaps
// counted once, fidelity/sphere_union.hpp) at the material's density.
dem::ClumpSpec read_clump(const config::Section& s, const dem::MaterialTable& materials);

}  // namespace mfdem::scene
