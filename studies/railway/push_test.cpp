#include "studies/railway/push_test.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "dem/state_file.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/section_simulation.hpp"
#include "studies/scene/progress.hpp"

namespace mfdem::railway {
namespace {

constexpr std::int64_t kEstimateSteps = 200;
constexpr double kMostPushSteps = 1e12;  // a month of a tiny bed's steps: beyond it, a typo  // steps timed for the estimate printed at the start

NetworkSample sample_network(const dem::Simulation& sim, const PushStudyConfig& c, double u, double velocity,
                             double mean_size, double volume) {
  const auto contacts = sim.contacts();
  double virial = 0.0;
  for (const auto& k : contacts) {
    const dem::Vec3 branch = sim.domain().nearest_image(sim.bodies().position[k.body_b] - sim.bodies().position[k.body_a]);
    virial += k.force.dot(branch);
  }
  NetworkSample s;
  s.u = u;
  s.mean_stress = virial / (3.0 * volume);
  const double shear_rate = velocity / c.geometry.sleeper_height;
  s.inertial_number = s.mean_stress > 0.0 ? shear_rate * mean_size / std::sqrt(s.mean_stress / c.ballast.density) : 0.0;
  s.coordination = 2.0 * static_cast<double>(contacts.size()) / std::max<double>(1.0, sim.bodies().size());
  return s;
}

// One component of the face forces, times sign, grouped by face.
ResistanceParts face_parts(const std::array<dem::Vec3, dem::kBoxFaces>& f, int axis, double sign) {
  ResistanceParts p;
  p.base = sign * f[dem::kMinusZ][axis];
  p.top = sign * f[dem::kPlusZ][axis];
  p.crib = sign * (f[dem::kMinusY][axis] + f[dem::kPlusY][axis]);
  p.shoulder = sign * (f[dem::kMinusX][axis] + f[dem::kPlusX][axis]);
  return p;
}

void summarise_curve(PushResult& r) {
  for (std::size_t k = 0; k < r.curve.size(); ++k)
    if (r.curve[k].force > r.peak_force) r.peak_force = r.curve[k].force, r.u_at_peak = r.curve[k].u, r.peak_sample = k;
  r.mean_force = mean_over_displacement(r.curve);
  r.final_heave = r.curve.back().heave;
  for (const auto& s : r.network) r.max_inertial_number = std::max(r.max_inertial_number, s.inertial_number);
}

void collect_end_state(const dem::Simulation& sim, PushResult& r) {
  r.end_contacts = sim.contacts();
  std::vector<double> magnitudes;
  for (const auto& contact : r.end_contacts) magnitudes.push_back(contact.force.norm());
  double sum = 0.0;
  for (double m : magnitudes) sum += m, r.max_contact_force = std::max(r.max_contact_force, m);
  r.mean_contact_force = magnitudes.empty() ? 0.0 : sum / magnitudes.size();
  r.contact_force_q999 = nearest_rank_quantile(magnitudes, 0.999);
  r.end_position = sim.bodies().position;
  for (std::size_t b = 0; b < r.end_position.size(); ++b)
    r.displacement.push_back(sim.domain().nearest_image(r.end_position[b] - r.start_position[b]));
}

}  // namespace

ResistanceParts resistance_parts(const std::array<dem::Vec3, dem::kBoxFaces>& f) { return face_parts(f, 0, -1.0); }

ResistanceParts support_parts(const std::array<dem::Vec3, dem::kBoxFaces>& f) { return face_parts(f, 2, 1.0); }

// The force on the sleeper through a face points into the sleeper: +axis on a minus face.
ResistanceParts pressing_parts(const std::array<dem::Vec3, dem::kBoxFaces>& f) {
  ResistanceParts p;
  p.base = f[dem::kMinusZ].z();
  p.top = -f[dem::kPlusZ].z();
  p.crib = f[dem::kMinusY].y() - f[dem::kPlusY].y();
  p.shoulder = f[dem::kMinusX].x() - f[dem::kPlusX].x();
  return p;
}

double bed_volume(const SectionGeometry& g) {
  const double profile = (g.crest_half_width() + g.toe_half_width()) * g.ballast_top();
  return profile * g.section_length - g.sleeper_length * g.sleeper_width * g.sleeper_height;
}

double nearest_rank_quantile(std::vector<double>& values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

std::string config_hash(const std::string& text) {
  std::uint64_t h = 14695981039346656037ULL;  // FNV-1a 64-bit offset basis
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ULL;  // and prime
  return fmt::format("{:016x}", h);
}

PushResult run_push(const Packing& packing, const PushStudyConfig& c, const PushRun& run) {
  StageSetup stage;
  stage.stone_friction = c.ballast.friction;
  stage.stone_local_damping = c.push.local_damping;
  stage.ball_friction = c.fidelity.ball_friction;
  dem::RigidBox sleeper = packing.sleeper;
  sleeper.velocity = dem::Vec3::Zero();  // speeds up over the ramp (below)
  sleeper.driven = {true, true, c.push.sleeper_held_vertically};
  stage.sleeper = sleeper;
  dem::Simulation sim = make_section_simulation(c, packing.domain, packing.bodies, stage);
  sim.set_initial_springs(packing.springs);
  sim.prepare();

  PushResult r;
  r.seed = packing.config.seed;
  r.config_hash = config_hash(c.text);
  r.push_config = c.text == packing.config.text ? c.name : fmt::format("{} ({})", c.name, c.source.string());
  r.velocity = run.velocity;
  r.distance = run.distance;
  r.time_step = sim.time_step();
  r.time_step_limit = sim.time_step_limit().limit;
  r.time_step_reason = sim.time_step_limit().reason;
  r.stones = sim.bodies().size();
  r.elements = sim.elements().size();
  r.sleeper_weight = sim.boxes()[0].mass * sim.settings().gravity.norm();
  r.sleeper_friction = sim.materials().pair(kBallast, kSleeper).friction;
  r.sleeper_held_vertically = c.push.sleeper_held_vertically;
  double mean_size = 0.0;
  for (const auto& s : packing.stones) {
    mean_size += s.size;
    r.stone_id.push_back(s.id);
  }
  mean_size /= std::max<std::size_t>(1, packing.stones.size());
  const double volume = bed_volume(c.geometry);
  r.start_position = sim.bodies().position;

  const double dt = sim.time_step();
  // The speed rises linearly over ramp_time (covering ramp_distance), then stays: an abrupt start
  // would hit the stones in front at full speed, a force peak that no quasi-static test has.
  const double ramp_distance = std::min(c.push.ramp_distance, run.distance);
  const double ramp_time = 2.0 * ramp_distance / run.velocity;
  const double step_count = (run.distance + 0.5 * run.velocity * ramp_time) / (run.velocity * dt);
  // A count llround cannot hold would wrap to nonsense; fewer than one step is no push.
  if (!(step_count >= 1.0 && step_count <= kMostPushSteps))
    throw config::ConfigError(fmt::format(
        "{}: a push of {:.6g} m at {:.6g} m/s takes {:.3g} steps of {:.3g} s: expected 1 to {:.0e} steps",
        c.source.string(), run.distance, run.velocity, step_count, dt, kMostPushSteps));
  const std::int64_t total = std::llround(step_count);
  const auto drive_speed = [&](std::int64_t step) {
    const double t = (static_cast<double>(step) + 0.5) * dt;  // mid-step
    return ramp_time > 0.0 ? run.velocity * std::min(1.0, t / ramp_time) : run.velocity;
  };
  const std::int64_t record_every = std::max<std::int64_t>(1, std::llround(c.push.record_interval / (run.velocity * dt)));
  const std::int64_t network_every = std::max<std::int64_t>(1, total / c.push.network_samples);
  const std::int64_t frame_every = std::max<std::int64_t>(1, std::llround(1e-3 / (run.velocity * dt)));
  const double x0 = sim.boxes()[0].centre.x(), z0 = sim.boxes()[0].centre.z();
  r.curve.push_back({0.0, -sim.box_force(0).x(), 0.0, 0.0, resistance_parts(sim.box_face_forces(0)),
                     support_parts(sim.box_face_forces(0)), pressing_parts(sim.box_face_forces(0)),
                     sim.active_contact_count()});
  r.network.push_back(sample_network(sim, c, 0.0, run.velocity, mean_size, volume));

  std::optional<dem::StateFile> frames;
  if (run.state_file) {
    frames.emplace(*run.state_file, sim, fmt::format("push of {} at {} m/s", c.name, run.velocity));
    frames->write_frame(sim);
  }
  scene::Progress progress("push", run.distance * 1e3, run.quiet);
  const auto start = std::chrono::steady_clock::now();
  double force_sum = 0.0;
  ResistanceParts parts_sum, support_sum, pressing_sum;
  std::int64_t in_interval = 0;
  std::int64_t k = 1;
  try {
    for (; k <= total; ++k) {
      sim.mutable_boxes()[0].velocity.x() = drive_speed(k - 1);
      sim.step();
      if (k == total) sim.check_stability();  // the guard runs every few hundred steps: and at the end
      if (k == kEstimateSteps && !run.quiet) {
        const double per_step = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / k;
        fmt::print(stderr, "push: {} stones, {} elements, time step {:.3g} s, {} steps, estimated {}\n", r.stones,
                   r.elements, dt, total, scene::format_duration(per_step * total));
      }
      force_sum += -sim.box_force(0).x();
      parts_sum += resistance_parts(sim.box_face_forces(0));
      support_sum += support_parts(sim.box_face_forces(0));
      pressing_sum += pressing_parts(sim.box_face_forces(0));
      ++in_interval;
      const double u = sim.boxes()[0].centre.x() - x0;
      if (k % record_every == 0 || k == total) {
        const double n = static_cast<double>(in_interval);
        r.curve.push_back({u, force_sum / n, sim.boxes()[0].centre.z() - z0, sim.time(), parts_sum / n,
                           support_sum / n, pressing_sum / n, sim.active_contact_count()});
        force_sum = 0.0;
        parts_sum = support_sum = pressing_sum = ResistanceParts{};
        in_interval = 0;
        progress.update(u * 1e3, fmt::format("u = {:.3f} mm  F = {:.3f} kN", u * 1e3, r.curve.back().force * 1e-3));
      }
      if (k % network_every == 0) r.network.push_back(sample_network(sim, c, u, run.velocity, mean_size, volume));
      if (frames && (k % frame_every == 0 || k == total)) frames->write_frame(sim);
    }
  } catch (const dem::StabilityError& e) {
    r.status = "unstable";
    r.message = e.what();
    if (frames && sim.last_good_state()) frames->write_snapshot(sim, *sim.last_good_state(), "last good state");
  }
  progress.finish();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.steps = std::min(k, total);
  summarise_curve(r);
  // After a guard tripped the state is not to be trusted: the curve up to then is the result.
  if (r.status == "finished") collect_end_state(sim, r);
  return r;
}

double mean_over_displacement(const std::vector<ForceSample>& curve) {
  double work = 0.0, u_before = 0.0;
  for (const auto& s : curve) work += s.force * (s.u - u_before), u_before = s.u;
  return u_before > 0.0 ? work / u_before : 0.0;
}

std::vector<double> window_mean_forces(const std::vector<ForceSample>& curve, double width) {
  if (curve.empty() || !(width > 0.0)) return {};
  const double u_last = curve.back().u;
  std::size_t windows = static_cast<std::size_t>(std::floor(u_last / width));
  // A tail of at least 0.4 w counts: a push to u_end stops within a step short of it.
  if (u_last - windows * width >= 0.4 * width) ++windows;
  std::vector<double> work(windows, 0.0), covered(windows, 0.0);
  double u_before = 0.0;
  for (const auto& s : curve) {
    // The interval (u_before, s.u] may straddle window edges: each window takes its overlap.
    for (std::size_t w = static_cast<std::size_t>(u_before / width); w < windows; ++w) {
      const double from = std::max(u_before, w * width), to = std::min(s.u, (w + 1) * width);
      if (to <= from) break;
      work[w] += s.force * (to - from);
      covered[w] += to - from;
    }
    u_before = s.u;
  }
  std::vector<double> means(windows);
  for (std::size_t w = 0; w < windows; ++w) means[w] = covered[w] > 0.0 ? work[w] / covered[w] : 0.0;
  return means;
}

}  // namespace mfdem::railway
