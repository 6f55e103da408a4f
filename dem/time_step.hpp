#pragma once
// Critical time step of the explicit integrator.
//
// For one linear contact of stiffness k between masses with reduced mass m_eff, velocity
// Verlet is stable for dt < 2/w, w = sqrt(k / m_eff); viscous damping of ratio beta lowers it
// to 2/w (sqrt(1 + beta^2) - beta). The tangential spring also turns the bodies, which lowers
// the effective mass to 1 / (1/m_a + r_a^2/I_a + 1/m_b + r_b^2/I_b) (2/7 m for a sphere on a
// wall); the rolling spring acts on the moments of inertia and couples with the tangential one
// (their 2 x 2 eigenproblem, time_step.cpp). The stiffest, lightest combination present sets
// the limit. A packed bed (several contacts per body) needs a safety factor below
// one: the automatic step is safety x limit, 0.2 by default (PFC and LIGGGHTS users take
// 0.1-0.3 of the Rayleigh or spring limit).
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/bodies.hpp"
#include "dem/material.hpp"
#include "dem/wall.hpp"

namespace mfdem::dem {

struct TimeStepLimit {
  double limit = 0.0;   // s
  std::string reason;   // which contact and body set it
  // False when no contact can occur (a lone body of its material, no walls): the limit is then
  // what a contact of its material would need, a step for the automatic choice, and a given step
  // above it is no danger.
  bool contact_possible = true;
};

// A given time step above the limit (Simulation::prepare without force_time_step): an input error
// the caller names with the key or option that forces it.
class TimeStepAboveLimitError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

TimeStepLimit critical_time_step(const Bodies& bodies, const Elements& elements,
                                 const MaterialTable& materials,
                                 const std::vector<PlaneWall>& walls);

}  // namespace mfdem::dem
