#pragma once
// The single-sleeper section of ballasted track (Jia, Markine & Guo 2023), every dimension a
// parameter, defaults from the design notes.
//
// Frame: x across the track (along the sleeper: the lateral push direction), y along the track
// (the section repeats with period section_length), z up; the rigid floor is z = 0 and the
// sleeper is centred at x = 0, y = section_length / 2. The ballast surface is flat at the
// sleeper's top (crib filled to the top) out to the shoulder's edge, then falls with the
// shoulder slope (horizontal per vertical, 1.5 for 1:1.5) to the floor.
#include <stdexcept>
#include <string>
#include <utility>

namespace mfdem::railway {

struct SectionGeometry {
  double sleeper_length = 2.6;        // m, along x
  double sleeper_width = 0.26;        // m, along y
  double sleeper_height = 0.21;       // m
  double sleeper_mass = 380.0;        // kg
  double section_length = 0.6;        // m, sleeper spacing along the track
  double depth_under_sleeper = 0.30;  // m of ballast below the sleeper's base
  double shoulder_width = 0.45;       // m beyond the sleeper's end, flat at the sleeper top
  double shoulder_slope = 1.5;        // horizontal per vertical of the shoulder's slope
  bool periodic_along_track = true;   // false: walls at y = 0 and y = section_length

  double ballast_top() const { return depth_under_sleeper + sleeper_height; }
  double crest_half_width() const { return 0.5 * sleeper_length + shoulder_width; }
  double toe_half_width() const { return crest_half_width() + shoulder_slope * ballast_top(); }
  double sleeper_base() const { return depth_under_sleeper; }
  // Height of the ballast surface at lateral position x (0 beyond the toe).
  double surface_height(double x) const;
  // Whether a point lies inside the ballast profile (and outside the sleeper).
  bool inside_ballast(double x, double z) const;
  bool inside_sleeper(double x, double y, double z) const;
};

// A geometry that cannot be built; `key` is the [section] key to change.
class GeometryError : public std::invalid_argument {
 public:
  GeometryError(std::string key_, const std::string& what) : std::invalid_argument(what), key(std::move(key_)) {}
  std::string key;
};

// Rejects geometry that cannot be built, naming the parameter, its value and what was expected;
// `largest_stone` is the largest stone's size in m. Throws GeometryError.
void validate(const SectionGeometry& g, double largest_stone);

}  // namespace mfdem::railway
