// A tiny single-sleeper bed for the push-test tests: 25 mm balls (every stone the equal-volume
// ball of a 25 mm stone, mu_r = 0.3 so the shoulders stand) in a 0.2 m periodic section under a
// 0.3 m x 0.06 m x 0.05 m sleeper; about 1,600 stones deposited, a 1 mm push.
#pragma once

namespace mfdem::test {

inline constexpr const char* kTinyBed = R"(
name = "tiny"
seed = 7
[section]
sleeper_length = 0.30
sleeper_width = 0.06
sleeper_height = 0.05
sleeper_mass = 2.5
section_length = 0.20
depth_under_sleeper = 0.08
shoulder_width = 0.04
[stones]
representation = "ball"
size = 0.025
[materials.ballast]          # Table 1 with rolling resistance, so the balls' shoulders stand
density = 2800.0
normal_stiffness = 2e7
shear_stiffness = 2e7
friction = 0.5
rolling_friction = 0.3
damping_ratio = 0.2
[preparation]
deposition_local_damping = 0.2
max_deposition_time = 0.25
max_settling_time = 0.1
[push]
distance = 1e-3
record_interval = 2e-5
network_samples = 5
)";

}  // namespace mfdem::test
