#pragma once
// Stability guards and the error they raise.
#include <cmath>
#include <stdexcept>
#include <string>

#include "dem/types.hpp"

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

// Thrown by Simulation::prepare when the bodies as given overlap beyond the guard before any
// step: input to refuse when a user placed them (a scene), an instability of the stage before
// when a program did (a bed handed on from one stage to the next).
class InitialOverlapError : public StabilityError {
 public:
  using StabilityError::StabilityError;
};

// A body's state is finite: one test of the sum, since a NaN or an infinity in any component
// makes the sum non-finite (a finite state would need components near 1e308 to overflow it).
inline bool finite_state(const Vec3& x, const Vec3& v, const Vec3& w) { return std::isfinite((x + v + w).sum()); }

}  // namespace mfdem::dem
