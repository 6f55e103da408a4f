#include "studies/railway/ball_growth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <optional>

#include "dem/neighbor_list.hpp"
#include "dem/state_file.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/packing.hpp"

namespace mfdem::railway {
namespace {

// A ball never starts below this fraction of its radius (a clump flat on the floor has its
// centre low; growing from less would take long and gain nothing).
constexpr double kSmallestStartFraction = 0.5;

}  // namespace

void check_balls_fit(const PushStudyConfig& c, const fidelity::ConvertedBed& converted) {
  if (!c.geometry.periodic_along_track) return;
  double largest = 0.0, smallest = std::numeric_limits<double>::infinity();
  for (const auto& b : converted.bodies)
    for (const auto& p : b.pebbles) largest = std::max(largest, p.radius), smallest = std::min(smallest, p.radius);
  // The neighbour search's own rule at the solver's automatic (smallest) skin.
  const double needed = dem::shortest_periodic_length(largest, dem::kBaseSkinPerSmallestRadius * smallest);
  // The crib is the sleeper's gap to its periodic image: no element may be wider
  // (dem::Simulation::check_boxes_clear_periodic_faces).
  const double crib = c.geometry.section_length - c.geometry.sleeper_width;
  if (2.0 * largest >= crib)
    throw config::ConfigError(fmt::format(
        "{}: section.sleeper_width = {} m leaves a crib of {:.4f} m to the next sleeper, narrower than this model's "
        "largest ball ({:.4f} m, the equal-volume ball of a large stone); keep that stone a clump (a lower layer, "
        "a wider zone) or widen the crib", c.source.string(), c.geometry.sleeper_width, crib, 2.0 * largest));
  if (c.geometry.section_length < needed)
    throw config::ConfigError(fmt::format(
        "{}: section.section_length = {} m is too short for this model's balls: a periodic section must hold "
        "{} x (largest ball diameter {:.4f} m + skin) = {:.4f} m; lengthen the section or keep the largest stones "
        "as clumps", c.source.string(), c.geometry.section_length, dem::kPeriodicReaches, 2.0 * largest, needed));
}

GrownBed grow_balls(const PushStudyConfig& c, const dem::Domain& domain, const fidelity::ConvertedBed& converted,
                    StageSetup setup, const std::filesystem::path& last_good) {
  GrownBed out;
  out.bodies = converted.bodies;
  out.springs = converted.springs;
  out.report.name = "grow";
  out.report.settled = true;
  if (c.fidelity.growth_friction) {
    setup.stone_friction = *c.fidelity.growth_friction;
    setup.ball_friction = *c.fidelity.growth_friction;
    setup.ball_rolling_friction = 0.0;
  }
  // The full-size bed sets the time step and the boundaries the balls must clear.
  const dem::Simulation full = make_section_simulation(c, domain, converted.bodies, setup);
  setup.time_step = c.time_step_safety * full.stability_limit().limit;
  const std::vector<double> start =
      fidelity::fitting_radii(converted, domain, full.walls(), full.boxes(), kSmallestStartFraction);

  std::vector<std::pair<dem::Index, double>> growing;  // the ball's element, its own radius
  double fraction_sum = 0.0;
  dem::Index element = 0;
  for (std::size_t b = 0; b < out.bodies.size(); element += static_cast<dem::Index>(out.bodies[b].pebbles.size()), ++b) {
    if (!converted.reshaped[b]) continue;
    const double own = out.bodies[b].pebbles.front().radius;
    out.smallest_start_fraction = std::min(out.smallest_start_fraction, start[b] / own);
    fraction_sum += start[b] / own;
    ++out.reshaped;
    if (start[b] < own) growing.emplace_back(element, own);
  }
  out.mean_start_fraction = out.reshaped ? fraction_sum / static_cast<double>(out.reshaped) : 1.0;
  if (growing.empty()) return out;

  std::vector<dem::ClumpSpec> small = converted.bodies;
  for (std::size_t b = 0; b < small.size(); ++b)
    if (converted.reshaped[b]) small[b].pebbles.front().radius = start[b];
  dem::Simulation sim = make_section_simulation(c, domain, small, setup);
  sim.set_initial_springs(converted.springs);
  sim.prepare();
  std::vector<double> from;
  for (const auto& g : growing) from.push_back(sim.elements().radius[g.first]);
  const double duration = c.fidelity.growth_time;
  const StageDrive drive = [&](dem::Simulation& s, double t) {
    const double share = std::min(1.0, (t + s.time_step()) / duration);  // reached by the step's end
    for (std::size_t k = 0; k < growing.size(); ++k)
      s.set_element_radius(growing[k].first, from[k] + share * (growing[k].second - from[k]));
  };
  // The converted bed as the growth starts, kept for a look if the growth turns unstable.
  std::optional<dem::StateFile> record;
  if (!last_good.empty()) {
    record.emplace(last_good, sim, fmt::format("growth of the converted balls of {}", c.name));
    record->write_frame(sim);
  }
  try {
    out.report = run_until_settled(sim, "grow", c.preparation.equilibrium_ratio, 1.0, duration, true,
                                   RestCriterion::kFixedTime, nullptr, 0.02, 2e-3, drive);
  } catch (const dem::StabilityError&) {
    if (record && sim.last_good_state()) record->write_snapshot(sim, *sim.last_good_state(), "last good state");
    throw;
  }
  record.reset();
  out.bodies = body_states(sim);
  // Exactly their own radii (the last step may fall short of growth_time by round-off).
  for (std::size_t b = 0; b < out.bodies.size(); ++b) out.bodies[b].pebbles = converted.bodies[b].pebbles;
  out.springs = sim.contact_springs();
  if (!sim.boxes().empty()) out.sleeper_centre = sim.boxes()[0].centre;
  return out;
}

}  // namespace mfdem::railway
