#pragma once
// Steps 1 and 2 of bed preparation (bed_preparation.hpp): the seeded stones of a study, and
// their placement in columns over the container floor so that no two touch at the start.
#include <cstdint>
#include <vector>

#include "dem/simulation.hpp"
#include "fidelity/grading.hpp"
#include "fidelity/shape_library.hpp"
#include "studies/railway/packing.hpp"

namespace mfdem::railway {

struct DrawnStone {
  StoneRecord record;
  dem::ClumpSpec body;  // centre of mass at the origin until placed
  double reach = 0.0;   // bounding radius about the centre of mass, m
};

// Stone k of a study: template, size and orientation from its own seeded stream
// (fidelity::StoneSampler), as a clump or as the ball of equal volume.
class StoneFactory {
 public:
  explicit StoneFactory(const PushStudyConfig& config);
  DrawnStone draw(std::int64_t k) const;
  // The upper size D of the grading (63 mm for 31.5/63 ballast): the smallest sieve that passes
  // at least 97 % by mass, as EN 13450 grades; the fixed size when there is one. The geometry
  // checks count stones of this size (the 1-3 % oversize is left out).
  double upper_size() const;
  // Mean solid volume of a stone, m^3, over the first `sample` draws.
  double mean_volume(int sample) const;

 private:
  const PushStudyConfig& config_;
  fidelity::ShapeLibrary library_;
  fidelity::StoneSampler sampler_;
};

// Columns on a grid over the container floor (toe to toe, the section's length) with the mean
// stone's footprint. Each stone, with a seeded sideways jitter (never into a wall), is dropped
// straight down onto the stones of its own and the neighbouring columns (large stones overhang
// their column) and rests where its pebbles first meet theirs, with a 2 % gap. Each starts down at drop_speed x its height / the
// highest stone's: a uniform collapse, quicker than a free fall from rest.
std::vector<DrawnStone> place_in_columns(const PushStudyConfig& config, std::vector<DrawnStone> stones);

}  // namespace mfdem::railway
