#pragma once
// The ways a scene places spheres: one by one, from a text file, or as a generated group.
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/config/config.hpp"

namespace mfdem::scene {

// [[sphere]]: position, radius, material, optional velocity and angular_velocity.
dem::SphereSpec read_sphere(const config::Section& s, const dem::MaterialTable& materials);

// [[sphere_file]]: path (relative to the scene file) of a text file with one sphere per line,
// "x y z radius" in metres, '#' comments; material; optional velocity.
std::vector<dem::SphereSpec> read_sphere_file(const config::Section& s,
                                              const dem::MaterialTable& materials);

// [[sphere_group]]: `count` spheres on a simple cubic lattice filling the region min..max in
// x, then y, then z order, radii uniform in radius*(1 +- radius_spread), seeded random velocity
// of magnitude up to `random_speed` on top of `velocity`.
std::vector<dem::SphereSpec> generate_sphere_group(const config::Section& s,
                                                   const dem::MaterialTable& materials,
                                                   std::uint64_t seed);

// `count` centres on a simple cubic lattice of spacing `pitch` filling the region min..max of
// section s, in x, then y, then z order; fails naming the key when the region is too small.
std::vector<dem::Vec3> lattice_centres(const config::Section& s, const dem::Vec3& min,
                                       const dem::Vec3& max, double pitch, long long count,
                                       const char* what);

// A path given by `key`, relative to the scene file that holds it.
std::filesystem::path path_beside_scene(const config::Section& s, std::string_view key);

// The material named by key "material"; fails naming the known ones.
int material_key(const config::Section& s, const dem::MaterialTable& materials);

}  // namespace mfdem::scene
