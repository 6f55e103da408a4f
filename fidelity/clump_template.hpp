#pragma once
// A clump template: the rigid multi-sphere shape of one kind of stone, ready to be placed in a
// simulation at any size, orientation and density.
//
// Frames and units. The template is written in its body frame: origin at the clump's centre of
// mass, axes along its principal axes of inertia (ascending moments: x is the long axis). Lengths
// are in units of the stone's size d, its intermediate dimension I (what a square sieve measures;
// see ShapeIndices), so a stone of sieve size d has pebbles at d * centre with radii d * radius,
//   mass           m = rho * volume * d^3                      [kg, rho in kg/m^3, d in m]
//   inertia        I_k = rho * principal_inertia[k] * d^5      [kg m^2]
// The input frame is the one the stone's surface (or pebbles) came in; a point x there maps to
//   x_body = input_to_principal * (x - centre_of_mass_input) / input_size.
//
// Mass properties are those of the union of the pebbles, overlaps counted once
// (sphere_union_mass_properties), because that is the solid the solver's contacts see.
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fidelity/bubble_pack.hpp"
#include "fidelity/pebble.hpp"
#include "fidelity/sphere_union.hpp"
#include "fidelity/stone_generator.hpp"
#include "fidelity/triangle_mesh.hpp"

namespace mfdem::fidelity {

// How well the clump approximates the stone's surface, both written in the body frame at unit
// size and unit density.
struct SurfaceFit {
  TriangleMesh surface;       // the stone's surface in the body frame
  double volume = 0.0;        // of the solid the surface encloses (divergence theorem)
  Vec3 centroid = Vec3::Zero();  // of that solid: its offset from the clump's centre of mass
  Mat3 inertia = Mat3::Zero();   // of that solid about its own centroid
  ShapeIndices indices;       // L, I (= 1), S of the surface
  double volume_error = 0.0;  // (V_clump - V_surface) / V_surface; negative: the clump is smaller
  double inertia_error = 0.0;  // || I_clump - I_surface ||_F / || I_surface ||_F, both tensors in
                               // the body frame about their own centroids, unit density
  double protrusion = 0.0;     // how far the pebbles reach outside the surface at most (radius
                               // minus the centre's distance to the surface), units of d
};

// The settings that regenerate a template (see shape_library.hpp).
struct ShapeSource {
  enum class Kind { generated, stl };
  Kind kind = Kind::generated;
  StoneSpec stone;        // kind == generated
  std::string stl_file;   // kind == stl: the path as written in the settings
  BubblePackOptions packing;  // min_radius in units of the stone's size d
  // Inscribed pebbles miss the stone's corners: 6 of them hold only 50-60 % of its volume. With
  // match_volume, all radii are then scaled by one factor so that the clump has the stone's
  // volume (and so its mass at a given sieve size); the pebbles then reach a little outside.
  bool match_volume = true;
};

struct ClumpTemplate {
  std::string name;
  std::vector<Pebble> pebbles;                 // body frame, units of d
  double volume = 0.0;                         // of the union of pebbles, units of d^3
  Vec3 principal_inertia = Vec3::Zero();       // ascending, per unit density, units of d^5
  Vec3 centre_of_mass_input = Vec3::Zero();    // input frame, input units
  Quat input_to_principal = Quat::Identity();  // rotation from the input frame to the body frame
  double input_size = 1.0;                     // the stone's size d in input units
  UnionMassProperties integration;             // error estimates and points of the integration
  std::optional<SurfaceFit> fit;               // absent for a clump given by its pebbles alone
  std::optional<ShapeSource> source;           // absent for a clump not built from settings

  double mass(double density, double size) const { return density * volume * size * size * size; }
  Vec3 inertia(double density, double size) const { return density * principal_inertia * std::pow(size, 5); }
  // Radius of the ball of the same volume (the clump's stand-in in a low-fidelity model).
  double equivalent_radius(double size) const;
  std::vector<Pebble> pebbles_at(double size) const;  // body frame, metres for size in metres
  Vec3 to_body(const Vec3& x_input) const;
};

// The template of a clump given by its pebbles in the input frame. input_size is the length that
// becomes 1 (the stone's size in input units). Throws std::invalid_argument for no pebbles, a
// radius that is not positive, or an integration that does not converge.
ClumpTemplate clump_from_pebbles(std::string name, std::span<const Pebble> input_pebbles, double input_size = 1.0,
                                 const UnionIntegrationOptions& integration = {});

// The factor f by which all radii must be scaled for the union to have `volume` (relative
// accuracy `tolerance` plus about 1e-5 from the integration): secant iteration on log V(f).
double radius_factor_for_volume(std::span<const Pebble> pebbles, double volume, double tolerance = 1e-5);

// Compares the clump with the closed surface it was made from (input frame, input units) and
// stores the result in clump.fit.
void fit_to_surface(ClumpTemplate& clump, const TriangleMesh& input_surface);

}  // namespace mfdem::fidelity
