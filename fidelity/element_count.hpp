#pragma once
// Element accounting: the cost measure of a fidelity choice. The paper counts the spheres of
// the stones (pebbles of clumps plus balls) as elements, and the sleeper and walls apart.
#include "dem/bodies.hpp"

namespace mfdem::fidelity {

struct ElementCount {
  long long bodies = 0;          // stones
  long long elements = 0;        // spheres of the stones
  long long clumps = 0;          // bodies with more than one element
  long long balls = 0;           // bodies with exactly one element
  double elements_per_body() const { return bodies ? double(elements) / double(bodies) : 0.0; }
};

ElementCount count_elements(const dem::Bodies& bodies);

}  // namespace mfdem::fidelity
