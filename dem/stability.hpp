#pragma once
// Stability guards and the error they raise.
#include <stdexcept>
#include <string>

namespace mfdem::dem {

struct GuardSettings {
  // An overlap beyond this fraction of the smaller radius means the springs are far too soft
  // for the load or the time step is too large.
  double max_overlap_fraction = 0.5;
  // Every this many steps the energy balance is checked and the last good state saved.
  int check_interval = 200;
  // Allowed growth of (kinetic + potential + elastic + dissipated - work in), as a fraction of
  // the energy scale (weight x domain height + largest kinetic plus elastic energy seen).
  double energy_growth = 0.05;
};

// Thrown when a run becomes unstable; `what()` names the cause, the body, the time and step.
class StabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mfdem::dem
