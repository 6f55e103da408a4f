#pragma once
// What a push test leaves behind, for people and for programs:
//   push.h5       attrs: format = "mfdem-push-1", definitions (the text of push_test.hpp's
//                 definitions), velocity, distance, peak_force, u_at_peak, max_contact_force,
//                 contact_force_q999, mean_contact_force, max_inertial_number, final_heave,
//                 time_step, steps, wall_seconds, stones, elements, status, message, seed,
//                 config_hash (FNV-1a of the config text), push_config (the config whose
//                 materials, guards and [push] ran: the packing's, or --config's), revision (git)
//                 /model attrs: policy, conversion_point, rolling_friction, ball_friction,
//                   clumps, balls, converted, elements, elements_before, element_ratio,
//                   springs_dropped, and after a re-settling resettle_wall_seconds,
//                   resettle_simulated_time, resettle_force_ratio, resettle_settled (1/0),
//                   resettle_sleeper_rise (m) (model_bed.hpp)
//                 /curve/{u, force, heave, time}                F(u) samples (m, N, m, s)
//                 /curve/contacts                              active element contacts at each sample
//                 /network/{u, mean_stress, inertial_number, coordination}
//                 /end_state/contact_body_a, contact_body_b    [contacts] stone indices
//                 /end_state/contact_point, contact_force      [contacts, 3] (force on b, N)
//                 /end_state/position, displacement            [stones, 3] m
//                 /end_state/stone_id                          [stones] seeded draw index
//   push_state.h5 (+ .xdmf): state frames at the start, every millimetre and the end
//   push_summary.toml and the printed table: the headline numbers, the model in [model] at the end.
//   rate_check.toml (--check-rate): the two pushes compared, half_velocity/ holding the second.
#include <filesystem>
#include <ostream>
#include <vector>

#include "studies/railway/push_test.hpp"

namespace mfdem::railway {

void write_push_file(const std::filesystem::path& path, const PushResult& result);
// F(u) of a push.h5: /curve/u and /curve/force. Throws std::runtime_error naming the file.
struct ForceCurve {
  std::vector<double> u, force;  // m, N
};
ForceCurve read_force_curve(const std::filesystem::path& path);
void write_push_summary(const std::filesystem::path& path, const PushResult& result, const Packing& packing);
void print_push_summary(std::ostream& out, const PushResult& result, const Packing& packing);
// The two pushes of --check-rate compared: the change of the peak force at half the velocity (the
// issue's quasi-static criterion: below kRateCriterion), of the mean force and of the mean F over
// each millimetre of u (a peak reached while F still rises moves by one slip event; the window
// means show whether the whole curve moved).
constexpr double kRateCriterion = 0.02;
struct RateCheck {
  double velocity = 0.0, half_velocity = 0.0;       // m/s
  double peak_change = 0.0, mean_change = 0.0;      // (half - full) / full
  double window = 1e-3;                             // m
  std::vector<double> window_full, window_half, window_change;
  double largest_window_change = 0.0;               // signed, of largest magnitude

  bool within_criterion() const { return peak_change < kRateCriterion && peak_change > -kRateCriterion; }
};
RateCheck compare_rates(const PushResult& full, const PushResult& half);
void print_rate_check(std::ostream& out, const PushResult& full, const PushResult& half, const RateCheck& check);
void write_rate_check(const std::filesystem::path& path, const RateCheck& check);

// The definitions of the outputs, printed in every report.
extern const char* const kPushDefinitions;

}  // namespace mfdem::railway
