// `mfdem run`: simulate a scene file, write HDF5 + XDMF frames and a summary.
#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>

#include "dem/state_file.hpp"
#include "fidelity/element_count.hpp"
#include "studies/cli/commands.hpp"
#include "studies/config/config_error.hpp"
#include "studies/scene/progress.hpp"
#include "studies/scene/scene_file.hpp"

namespace mfdem {
namespace {

long long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

// Steps of the whole run and between outputs, refused (naming the file and the keys) when the
// duration and the step make a count that is below one or past what a run can hold: llround
// of 1e300 / 1e-6 would wrap to nonsense and the run would "finish" after no step.
struct StepPlan {
  std::int64_t total = 0, output_every = 1;
};

constexpr double kMostRunSteps = 1e12;

StepPlan step_plan(const scene::Scene& s, const dem::Simulation& sim, const std::filesystem::path& file) {
  const double dt = sim.time_step();
  const double total = s.duration / dt, between = s.output_interval / dt;
  if (!(total >= 1.0 && total <= kMostRunSteps))
    throw config::ConfigError(fmt::format("{}: duration = {:.6g} s at time step {:.6g} s makes {:.3g} steps: "
                                          "expected 1 to {:.0e}", file.string(), s.duration, dt, total,
                                          kMostRunSteps));
  if (!(between <= kMostRunSteps))
    throw config::ConfigError(fmt::format("{}: output_interval = {:.6g} s at time step {:.6g} s makes {:.3g} "
                                          "steps between outputs: expected at most {:.0e}", file.string(),
                                          s.output_interval, dt, between, kMostRunSteps));
  return {std::llround(total), std::max<std::int64_t>(1, std::llround(between))};
}

struct RunTotals {
  double wall_seconds = 0.0;  // stepping loop only (no output)
  std::int64_t steps = 0;
  std::string status = "finished";
  std::string message;
};

void write_summary(const std::filesystem::path& file, const scene::Scene& scene,
                   const dem::Simulation& sim, const RunTotals& t) {
  const auto count = fidelity::count_elements(sim.bodies());
  const dem::EnergyReport e = sim.energy();
  const double contacts = sim.active_contact_count();
  const double element_steps = double(count.elements) * double(t.steps);
  std::ofstream out(file);
  out << "# mfdem run summary; energies in J, times in s\n"
      << fmt::format("scene = \"{}\"\nstatus = \"{}\"\n", scene.source.string(), t.status);
  if (!t.message.empty()) out << fmt::format("message = \"\"\"{}\"\"\"\n", t.message);
  out << fmt::format(
      "seed = {}\nthreads = {}\nbodies = {}\nelements = {}\nsteps = {}\ntime_step = {:.9g}\n"
      "critical_time_step = {:.9g}\nfinal_time = {:.9g}\nwall_seconds = {:.6g}\n"
      "element_steps_per_second = {:.6g}\ncontacts = {}\ncontacts_per_element = {:.6g}\n"
      "neighbour_rebuilds = {}\npeak_rss_bytes = {}\nkinetic_energy = {:.9g}\n"
      "elastic_energy = {:.9g}\ndissipated_energy = {:.9g}\nwork_by_walls = {:.9g}\n"
      "energy_total = {:.9g}\n",
      scene.seed, omp_get_max_threads(), count.bodies, count.elements, t.steps, sim.time_step(),
      sim.time_step_limit().limit, sim.time(), t.wall_seconds,
      t.wall_seconds > 0 ? element_steps / t.wall_seconds : 0.0, static_cast<long long>(contacts),
      count.elements ? contacts / count.elements : 0.0, sim.neighbour_rebuilds(), peak_rss_bytes(),
      e.kinetic(), e.elastic, e.dissipated(), e.work_by_walls, e.total());
}

}  // namespace

namespace {

// Prepares the scene's solver; what the solver refuses at set-up is the scene's error, named with
// its file, the key to change and (for the time step) the key and option that force it.
void prepare_scene(dem::Simulation& sim, const std::filesystem::path& file) {
  try {
    sim.prepare();
  } catch (const dem::InitialOverlapError& e) {
    throw config::ConfigError(fmt::format("{}: {}; place them apart", file.string(), e.what()));
  } catch (const dem::TimeStepAboveLimitError& e) {
    throw config::ConfigError(fmt::format(
        "{}: [simulation] time_step: {} ([simulation] force_time_step = true, or `mfdem run --force-dt`)",
        file.string(), e.what()));
  } catch (const dem::PeriodicBoxTooShortError& e) {
    throw config::ConfigError(fmt::format(
        "{}: [domain] min, max along {}: the periodic length {:.6g} m is below {:.6g} m, twice the largest "
        "diameter plus the skin; lengthen the domain along {} or drop \"{}\" from [domain] periodic",
        file.string(), "xyz"[e.axis], e.length, e.shortest, "xyz"[e.axis], "xyz"[e.axis]));
  } catch (const std::invalid_argument& e) {
    throw config::ConfigError(fmt::format("{}: {}", file.string(), e.what()));
  }
}

}  // namespace

void check_scene_file(const std::filesystem::path& file) {
  const scene::Scene s = scene::load_scene(file);
  dem::Simulation sim = scene::make_simulation(s);
  prepare_scene(sim, file);
  step_plan(s, sim, file);
}

int run_scene_command(const RunOptions& options) {
  const bool quiet = options.common.quiet;
  std::optional<std::uint64_t> seed;
  if (options.common.seed_given) seed = options.common.seed;
  scene::Scene s = scene::load_scene(options.scene, seed);
  if (options.force_dt) s.settings.force_time_step = true;
  dem::Simulation sim = scene::make_simulation(s);
  try {
    prepare_scene(sim, options.scene);
  } catch (const config::ConfigError& e) {
    std::cerr << "mfdem: error: " << e.what() << "\n";
    return 2;
  }
  const StepPlan plan = step_plan(s, sim, options.scene);
  const std::int64_t total_steps = plan.total, output_every = plan.output_every;
  const auto count = fidelity::count_elements(sim.bodies());
  if (!quiet)
    fmt::print("mfdem run {}\n  bodies {}  elements {}  walls {}  threads {}\n  time step {:.4g} s "
               "(critical {:.4g} s, set by the {})\n  steps {}  output every {} steps\n",
               options.scene.string(), count.bodies, count.elements, sim.walls().size(),
               omp_get_max_threads(), sim.time_step(), sim.time_step_limit().limit,
               sim.time_step_limit().reason, total_steps, output_every);

  std::filesystem::create_directories(options.common.out);
  const auto state_path = options.common.out / "state.h5";
  dem::StateFile state(state_path, sim, "scene " + options.scene.string());
  state.write_frame(sim);

  RunTotals totals;
  scene::Progress progress("run", double(total_steps), quiet);
  int exit_status = 0;
  try {
    while (totals.steps < total_steps) {
      // Bursts end at output steps, and are short enough that the progress line moves.
      constexpr std::int64_t kProgressBurst = 500;
      const std::int64_t burst = std::min({output_every - sim.step_count() % output_every,
                                           total_steps - totals.steps, kProgressBurst});
      const auto start = std::chrono::steady_clock::now();
      for (std::int64_t k = 0; k < burst; ++k) sim.step();
      totals.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      totals.steps += burst;
      if (totals.steps == total_steps) sim.check_stability();  // the guard runs every few hundred steps: and at the end
      if (sim.step_count() % output_every == 0 || totals.steps == total_steps) state.write_frame(sim);
      progress.update(double(totals.steps),
                      fmt::format("t = {:.4g} s  KE = {:.3g} J", sim.time(), sim.energy().kinetic()));
    }
    progress.finish();
  } catch (const dem::StabilityError& e) {
    progress.finish();
    totals.steps = sim.step_count();  // the steps completed before the guard tripped
    totals.status = "unstable";
    totals.message = e.what();
    if (sim.last_good_state()) state.write_snapshot(sim, *sim.last_good_state(), "last good state");
    std::cerr << "mfdem: error: " << e.what() << "\n";
    exit_status = 3;
  }
  write_summary(options.common.out / "summary.toml", s, sim, totals);
  if (!quiet) {
    const dem::EnergyReport e = sim.energy();
    const double rate = totals.wall_seconds > 0 ? count.elements * double(totals.steps) / totals.wall_seconds : 0.0;
    fmt::print("\n  {:<34} {}\n", "status", totals.status);
    fmt::print("  {:<34} {:.6g} s in {} steps\n", "simulated time", sim.time(), totals.steps);
    fmt::print("  {:<34} {:.3f} s ({:.3g} element-steps/s)\n", "wall time of the steps", totals.wall_seconds, rate);
    fmt::print("  {:<34} {:.4g}\n", "contacts per element", double(sim.active_contact_count()) / count.elements);
    fmt::print("  {:<34} {:.6g} J\n", "kinetic energy", e.kinetic());
    fmt::print("  {:<34} {:.6g} J (damping {:.4g}, friction {:.4g}, local {:.4g})\n", "dissipated",
               e.dissipated(), e.dissipated_damping, e.dissipated_friction, e.dissipated_local);
    fmt::print("  {:<34} {:.6g} J\n", "work by walls", e.work_by_walls);
    for (std::size_t w = 0; w < sim.walls().size(); ++w) {
      const auto& f = sim.wall_force(static_cast<int>(w));
      fmt::print("  force on wall {:<20} ({:.4g}, {:.4g}, {:.4g}) N\n", sim.walls()[w].name, f[0], f[1], f[2]);
    }
    fmt::print("  {:<34} {} ({} frames), {}\n", "results", state_path.string(), state.frame_count(),
               (options.common.out / "summary.toml").string());
  }
  return exit_status;
}

}  // namespace mfdem
