#pragma once
// The solver set up for one stage of a single-sleeper study: the stones, the floor, walls along
// the track unless the section is periodic, optional container walls across the track, and the
// sleeper as a rigid box. Materials are always ballast (0), sleeper (1), floor (2), and ball (3)
// when some stone is a ball (a body of material kBall: push_config.hpp, FidelitySettings).
#include <optional>
#include <vector>

#include "dem/simulation.hpp"
#include "studies/railway/push_config.hpp"

namespace mfdem::railway {

constexpr int kBallast = 0, kSleeper = 1, kFloor = 2, kBall = 3;

struct StageSetup {
  double stone_friction = 0.5;         // mu of the ballast material in this stage
  double stone_local_damping = 0.0;    // alpha of the stones in this stage
  std::optional<double> ball_friction; // mu of the balls in this stage; none: stone_friction
  std::optional<double> ball_rolling_friction;  // mu_r of the balls in this stage; none: [fidelity]'s
  std::optional<double> time_step;     // s; none: time_step_safety x the limit of this bed
  bool container_walls = false;        // vertical walls at x = +-toe (deposition)
  double gravity_factor = 1.0;         // gravity this many times g (consolidation)
  std::optional<dem::RigidBox> sleeper;
};

// A stone keeps material kBall (a ball); every other stone is made kBallast.
dem::Simulation make_section_simulation(const PushStudyConfig& config, const dem::Domain& domain,
                                        const std::vector<dem::ClumpSpec>& stones, const StageSetup& stage);

// The domain of a section: x over the toe-to-toe width plus a margin, y over one sleeper spacing
// (periodic or walled), z from the floor to `top`.
dem::Domain section_domain(const PushStudyConfig& config, double top);

}  // namespace mfdem::railway
