#pragma once
// The file format of one clump template: TOML, lengths in units of the stone's size d.
//
//   format = "mfdem clump template 1"
//   name = "ballast_01"
//   [source]       settings that regenerate it: kind = "generated" (seed, elongation, flatness,
//                  vertices) or "stl" (stl = path); pebbles, min_radius, grid_cells, rule,
//                  match_volume
//   [clump]        volume, principal_inertia, centre_of_mass_input, input_to_principal
//                  (quaternion w, x, y, z), input_size, pebbles = [[x, y, z, r], ...]
//   [integration]  volume_error, centroid_error, inertia_error, points
//   [surface]      the stone's surface in the body frame: vertices, triangles, volume, centroid,
//                  inertia (3 x 3), length, intermediate, thickness, volume_error, inertia_error,
//                  protrusion
// Numbers are written in their shortest round-trip form, so a save and a load give back the same
// values.
#include <filesystem>
#include <string>
#include <string_view>

#include "fidelity/clump_template.hpp"

namespace mfdem::fidelity {

std::string format_template(const ClumpTemplate& clump);
void save_template(const ClumpTemplate& clump, const std::filesystem::path& file);

// Throws ShapeError "<source>:<line>: <key>: <problem>" for a missing key, a wrong type or a value
// out of range.
ClumpTemplate parse_template(std::string_view text, std::string_view source);
ClumpTemplate load_template(const std::filesystem::path& file);

}  // namespace mfdem::fidelity
