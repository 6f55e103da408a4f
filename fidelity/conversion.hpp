#pragma once
// Re-representing a prepared bed by a fidelity policy (policy.hpp): a change of data, not of
// types. Every body keeps its place in the list (so stone identities and every per-stone output
// compare stone by stone); a stone the policy makes a ball is replaced by the sphere of equal
// volume (its mass / density, so equal mass) at its centre of mass, with its velocity, angular
// velocity and orientation (a ball's frame is unused). A clump of one pebble at its centre is
// already that sphere: it is kept bitwise, only its material changes. Balls stay balls whatever
// the policy says (rebuilding a clump needs its template).
//
// The springs of the bed's contacts (dem::SpringState, element-indexed) follow: those of a
// contact that a converted stone takes part in are dropped (its geometry changed; not for a
// centred one-pebble clump, whose geometry stays), the others are re-indexed to the new elements.
#include <cstdint>
#include <vector>

#include "dem/domain.hpp"
#include "dem/rigid_box.hpp"
#include "dem/simulation.hpp"
#include "dem/wall.hpp"
#include "fidelity/policy.hpp"

namespace mfdem::fidelity {

// Where a policy measures stones from: the floor's height and the sleeper (an axis-aligned box,
// its periodic images included along the domain's periodic axes).
struct BedFrame {
  double floor_height = 0.0;  // m
  dem::RigidBox sleeper;
  dem::Domain domain;

  BedScale scale() const { return {dem::box_bottom(sleeper) - floor_height}; }
};

StoneGeometry measure_stone(const dem::ClumpSpec& stone, const BedFrame& frame);

// The ball of equal volume replacing `clump` (density in kg/m^3); its material is `material`.
dem::ClumpSpec ball_of(const dem::ClumpSpec& clump, double density, int material);

struct ConvertedBed {
  std::vector<dem::ClumpSpec> bodies;
  std::vector<std::uint8_t> reshaped;   // per body: 1 if it became a ball of another shape now
  std::vector<dem::SpringState> springs;
  std::int64_t clumps = 0, balls = 0;   // stones of each kind after the conversion
  std::int64_t converted = 0;           // clumps made balls now
  std::int64_t elements_before = 0, elements_after = 0;
  std::int64_t springs_dropped = 0;
};

// Converts every stone whose material is not `ball_material` and which `policy` makes a ball.
ConvertedBed convert_bed(const std::vector<dem::ClumpSpec>& bodies, const std::vector<dem::SpringState>& springs,
                         const Policy& policy, const BedFrame& frame, double density, int ball_material);

// An equal-volume ball is wider than its clump across the clump's short axes, so in a packed bed
// it overlaps its neighbours (tiny bed: by more than half its radius). It is started at the
// largest radius, up to its own, at which it touches no pebble of another body, no other
// reshaped ball (two share the gap in proportion to their radii), no wall and no box, and never
// below `smallest_fraction` of its own; the re-settling grows it to size. Returns a radius per
// body (its own for bodies not reshaped).
std::vector<double> fitting_radii(const ConvertedBed& bed, const dem::Domain& domain,
                                  const std::vector<dem::PlaneWall>& walls, const std::vector<dem::RigidBox>& boxes,
                                  double smallest_fraction);

}  // namespace mfdem::fidelity
