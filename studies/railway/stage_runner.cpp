#include "studies/railway/stage_runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <optional>
#include <stdexcept>

#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

constexpr std::int64_t kEstimateSteps = 200;  // steps timed for the estimate printed at the start

// The stones' positions at the last checks of one creep window, oldest first: their mean
// displacement between the oldest kept and now, over the length scale.
class CreepMeter {
 public:
  CreepMeter(double length_scale, std::int64_t checks_per_window)
      : length_scale_(length_scale), kept_(static_cast<std::size_t>(checks_per_window) + 1) {}

  double record(const dem::Simulation& sim) {
    if (positions_.size() == kept_) positions_.pop_front();
    positions_.push_back(sim.bodies().position);
    const auto& first = positions_.front();
    const auto& now = positions_.back();
    double sum = 0.0;
    for (std::size_t b = 0; b < now.size(); ++b) sum += sim.domain().nearest_image(now[b] - first[b]).norm();
    return sum / static_cast<double>(std::max<std::size_t>(1, now.size())) / length_scale_;
  }
  // True once the positions span the whole window.
  bool full() const { return positions_.size() == kept_; }

 private:
  double length_scale_;  // m
  std::size_t kept_;
  std::deque<std::vector<dem::Vec3>> positions_;
};

}  // namespace

StageReport run_until_settled(dem::Simulation& sim, const std::string& name, double ratio_target,
                              double energy_scale, double max_time, bool quiet, RestCriterion criterion,
                              dem::StateFile* frames, double frame_interval,
                              double check_interval, const StageDrive& drive, const CreepGoal& creep) {
  StageReport r;
  r.name = name;
  const auto start = std::chrono::steady_clock::now();
  const double t0 = sim.time();
  const std::int64_t s0 = sim.step_count();
  const std::int64_t every = std::max<std::int64_t>(1, std::llround(check_interval / sim.time_step()));
  const std::int64_t limit = std::llround(max_time / sim.time_step());
  scene::Progress progress(fmt::format("{:<10}", name), max_time, quiet);
  const std::int64_t frame_every = std::max<std::int64_t>(1, std::llround(frame_interval / sim.time_step()));
  if (frames) frames->write_frame(sim);
  int below = 0;
  std::optional<CreepMeter> creep_meter;
  if (creep.active() && criterion == RestCriterion::kForcesAndEnergy) {
    if (!(creep.length_scale > 0.0)) throw std::invalid_argument("run_until_settled: a creep goal needs a length scale");
    creep_meter.emplace(creep.length_scale, std::max<std::int64_t>(1, std::llround(creep.window / (every * sim.time_step()))));
  }
  for (std::int64_t k = 1; k <= limit; ++k) {
    if (drive) drive(sim, static_cast<double>(k - 1) * sim.time_step());
    sim.step();
    if (k == kEstimateSteps && !quiet) {
      const double per_step = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / k;
      // A stage that starts with few contacts (a deposition still falling) gets slower as they
      // form: on the standard bed the packed steps cost about twice the falling ones.
      const bool few_contacts = sim.active_contact_count() < sim.elements().size();
      fmt::print(stderr, "{}: {} bodies, {} elements, time step {:.3g} s, at most {} steps ({} s), estimated at most {}{}\n",
                 name, sim.bodies().size(), sim.elements().size(), sim.time_step(), limit, max_time,
                 scene::format_duration(per_step * limit),
                 few_contacts ? " at the present rate (few contacts yet; the packed bed steps up to 2x slower)" : "");
    }
    if (frames && k % frame_every == 0) frames->write_frame(sim);
    if (k % every != 0) continue;
    r.unbalanced_force_ratio = sim.unbalanced_force_ratio();
    const double kinetic = sim.energy().kinetic() / energy_scale;
    const bool forces_balanced =
        criterion == RestCriterion::kEnergyOnly || r.unbalanced_force_ratio < ratio_target;
    r.check_time.push_back(sim.time() - t0);
    r.check_force_ratio.push_back(r.unbalanced_force_ratio);
    r.check_kinetic_ratio.push_back(kinetic);
    if (!sim.boxes().empty()) r.check_sleeper_base.push_back(dem::box_bottom(sim.boxes()[0]));
    below = criterion != RestCriterion::kFixedTime && forces_balanced && kinetic < ratio_target ? below + 1 : 0;
    bool crept_to_rest = false;
    if (creep_meter) {
      r.check_creep.push_back(creep_meter->record(sim));
      crept_to_rest = creep_meter->full() && kinetic < ratio_target && r.check_creep.back() < creep.ratio;
    }
    progress.update(sim.time() - t0,
                    fmt::format("unbalanced force ratio {:.2e}, kinetic/(M g d) {:.2e} (target {:.0e}){}",
                                r.unbalanced_force_ratio, kinetic, ratio_target,
                                creep_meter ? fmt::format(", creep {:.1e} (target {:.0e})", r.check_creep.back(), creep.ratio)
                                            : std::string()));
    if (below >= 2 || crept_to_rest) {
      r.settled = true;
      r.settled_by_creep = below < 2;
      break;
    }
  }
  progress.finish();
  sim.check_stability();  // the guard runs every few hundred steps: and at the end
  if (criterion == RestCriterion::kFixedTime) r.settled = true;
  if (frames) frames->write_frame(sim);
  r.unbalanced_force_ratio = sim.unbalanced_force_ratio();
  r.simulated_time = sim.time() - t0;
  r.steps = sim.step_count() - s0;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace mfdem::railway
