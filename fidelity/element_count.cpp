#include "fidelity/element_count.hpp"

namespace mfdem::fidelity {

ElementCount count_elements(const dem::Bodies& bodies) {
  ElementCount c;
  for (dem::Index b = 0; b < bodies.size(); ++b) {
    const long long n = bodies.element_end(b) - bodies.element_begin(b);
    ++c.bodies;
    c.elements += n;
    (n > 1 ? c.clumps : c.balls) += 1;
  }
  return c;
}

}  // namespace mfdem::fidelity
