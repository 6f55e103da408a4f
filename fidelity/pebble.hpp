#pragma once
// One sphere of a clump: its centre and radius in the clump's frame.
#include "dem/types.hpp"

namespace mfdem::fidelity {

struct Pebble {
  dem::Vec3 centre;
  double radius = 0.0;
};

}  // namespace mfdem::fidelity
