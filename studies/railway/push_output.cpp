#include "studies/railway/push_output.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "dem/hdf5_io.hpp"
#include "studies/scene/progress.hpp"
#include "studies/scene/text_wrap.hpp"

namespace mfdem::railway {

const char* const kPushDefinitions =
    "F(u): minus the sum of the stones' contact forces on the sleeper along the push (+x), mean over each "
    "record interval, against the sleeper's lateral displacement u. Peak lateral force: max F(u) for u in "
    "[0, u_end]. Mean F: the work done on the bed over the push / u_end. Maximum particle contact force: "
    "max |f| over stone-stone contacts at u_end; q99.9: its "
    "99.9 % nearest-rank quantile. Inertial number I = (v / sleeper height) d_mean / sqrt(p / rho), p the "
    "mean stress of the stone contacts over the bed. Base, crib, shoulder: the parts of F carried by the "
    "sleeper's bottom face, its two sides along the track and its two ends (each contact counted to the face "
    "it leans on most). support_*: the same split of the upward force on the sleeper, the part of its "
    "weight each face carries. pressing_*: the normal force the stones press each face group with (both crib "
    "sides summed, both ends summed); friction on the base and crib sides gives at most about mu x (pressing_base + pressing_crib) of F (edge contacts aside).";

namespace {

// Prose printed with a report or written as a comment is broken into lines of this width.
constexpr std::size_t kTextWidth = 100;

// The [push] sleeper_vertical value the push ran with, as the config spells it.
const char* sleeper_vertical(const PushResult& r) { return r.sleeper_held_vertically ? "held" : "free"; }

// The model's record as (name, number) pairs; the re-settling's only when there was one.
std::vector<std::pair<std::string, double>> model_numbers(const ModelReport& m) {
  std::vector<std::pair<std::string, double>> v = {
      {"rolling_friction", m.rolling_friction}, {"ball_friction", m.ball_friction},
      {"clumps", static_cast<double>(m.clumps)}, {"balls", static_cast<double>(m.balls)},
      {"converted", static_cast<double>(m.converted)}, {"elements", static_cast<double>(m.elements)},
      {"elements_before", static_cast<double>(m.elements_before)}, {"element_ratio", m.element_ratio()},
      {"springs_dropped", static_cast<double>(m.springs_dropped)}, {"reshaped", static_cast<double>(m.reshaped)},
      {"smallest_start_fraction", m.smallest_start_fraction}, {"mean_start_fraction", m.mean_start_fraction}};
  if (m.resettling) {
    v.push_back({"resettle_wall_seconds", m.resettling->wall_seconds});
    v.push_back({"resettle_simulated_time", m.resettling->simulated_time});
    v.push_back({"resettle_force_ratio", m.resettling->unbalanced_force_ratio});
    v.push_back({"resettle_settled", m.resettling->settled ? 1.0 : 0.0});
    v.push_back({"resettle_settled_by_creep", m.resettling->settled_by_creep ? 1.0 : 0.0});
    if (m.resettling->sleeper_base && m.resettling->sleeper_base_start)
      v.push_back({"resettle_sleeper_rise", *m.resettling->sleeper_base - *m.resettling->sleeper_base_start});
  }
  return v;
}

template <class T, class F>
std::vector<double> column(const std::vector<T>& rows, F field) {
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& r : rows) out.push_back(field(r));
  return out;
}

}  // namespace

void write_push_file(const std::filesystem::path& path, const PushResult& r) {
  using namespace dem::h5;
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error("cannot create " + path.string());
  write_attribute(file, "format", std::string("mfdem-push-1"));
  write_attribute(file, "definitions", std::string(kPushDefinitions));
  write_attribute(file, "status", r.status);
  write_attribute(file, "message", r.message);
  write_attribute(file, "sleeper_vertical", std::string(sleeper_vertical(r)));
  const std::pair<const char*, double> numbers[] = {
      {"velocity", r.velocity}, {"distance", r.distance}, {"peak_force", r.peak_force},
      {"mean_force", r.mean_force},
      {"u_at_peak", r.u_at_peak}, {"max_contact_force", r.max_contact_force},
      {"contact_force_q999", r.contact_force_q999}, {"mean_contact_force", r.mean_contact_force},
      {"max_inertial_number", r.max_inertial_number}, {"final_heave", r.final_heave},
      {"sleeper_weight", r.sleeper_weight},
      {"sleeper_friction", r.sleeper_friction},
      {"time_step", r.time_step}, {"time_step_limit", r.time_step_limit}, {"steps", static_cast<double>(r.steps)}, {"wall_seconds", r.wall_seconds},
      {"stones", static_cast<double>(r.stones)}, {"elements", static_cast<double>(r.elements)}};
  for (const auto& [name, value] : numbers) write_attribute(file, name, value);
  write_attribute(file, "seed", static_cast<double>(r.seed));
  write_attribute(file, "config_hash", r.config_hash);
  write_attribute(file, "push_config", r.push_config);
  write_attribute(file, "revision", r.revision);
  write_attribute(file, "time_step_reason", r.time_step_reason);
  {
    const hid_t model = make_group(file, "model");
    write_attribute(model, "policy", r.model.policy);
    write_attribute(model, "conversion_point", r.model.conversion_point);
    for (const auto& [name, value] : model_numbers(r.model)) write_attribute(model, name, value);
    H5Gclose(model);
  }
  write_doubles(file, "curve/u", column(r.curve, [](auto& s) { return s.u; }));
  write_doubles(file, "curve/force", column(r.curve, [](auto& s) { return s.force; }));
  write_doubles(file, "curve/heave", column(r.curve, [](auto& s) { return s.heave; }));
  write_doubles(file, "curve/time", column(r.curve, [](auto& s) { return s.time; }));
  write_doubles(file, "curve/contacts", column(r.curve, [](auto& s) { return double(s.contacts); }));
  write_doubles(file, "curve/base", column(r.curve, [](auto& s) { return s.parts.base; }));
  write_doubles(file, "curve/crib", column(r.curve, [](auto& s) { return s.parts.crib; }));
  write_doubles(file, "curve/shoulder", column(r.curve, [](auto& s) { return s.parts.shoulder; }));
  write_doubles(file, "curve/top", column(r.curve, [](auto& s) { return s.parts.top; }));
  write_doubles(file, "curve/support_base", column(r.curve, [](auto& s) { return s.support.base; }));
  write_doubles(file, "curve/support_crib", column(r.curve, [](auto& s) { return s.support.crib; }));
  write_doubles(file, "curve/support_shoulder", column(r.curve, [](auto& s) { return s.support.shoulder; }));
  write_doubles(file, "curve/support_top", column(r.curve, [](auto& s) { return s.support.top; }));
  write_doubles(file, "curve/pressing_base", column(r.curve, [](auto& s) { return s.pressing.base; }));
  write_doubles(file, "curve/pressing_crib", column(r.curve, [](auto& s) { return s.pressing.crib; }));
  write_doubles(file, "curve/pressing_shoulder", column(r.curve, [](auto& s) { return s.pressing.shoulder; }));
  write_doubles(file, "network/u", column(r.network, [](auto& s) { return s.u; }));
  write_doubles(file, "network/mean_stress", column(r.network, [](auto& s) { return s.mean_stress; }));
  write_doubles(file, "network/inertial_number", column(r.network, [](auto& s) { return s.inertial_number; }));
  write_doubles(file, "network/coordination", column(r.network, [](auto& s) { return s.coordination; }));
  std::vector<dem::Index> a, b, ids;
  std::vector<dem::Vec3> point, force;
  for (const auto& c : r.end_contacts) {
    a.push_back(c.body_a);
    b.push_back(c.body_b);
    point.push_back(c.point);
    force.push_back(c.force);
  }
  for (auto id : r.stone_id) ids.push_back(static_cast<dem::Index>(id));
  write_ints(file, "end_state/contact_body_a", a);
  write_ints(file, "end_state/contact_body_b", b);
  write_vec3s(file, "end_state/contact_point", point);
  write_vec3s(file, "end_state/contact_force", force);
  write_vec3s(file, "end_state/position", r.end_position);
  write_vec3s(file, "end_state/displacement", r.displacement);
  write_ints(file, "end_state/stone_id", ids);
  H5Fclose(file);
}

ForceCurve read_force_curve(const std::filesystem::path& path) {
  hid_t file = -1;
  H5E_BEGIN_TRY { file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); }
  H5E_END_TRY;
  if (file < 0) throw std::runtime_error(fmt::format("{}: cannot open it as an HDF5 file", path.string()));
  if (H5Lexists(file, "curve", H5P_DEFAULT) <= 0) {
    H5Fclose(file);
    throw std::runtime_error(fmt::format("{}: no /curve group (not a push.h5)", path.string()));
  }
  ForceCurve curve{dem::h5::read_doubles(file, "curve/u"), dem::h5::read_doubles(file, "curve/force")};
  H5Fclose(file);
  return curve;
}

void write_push_summary(const std::filesystem::path& path, const PushResult& r, const Packing& p) {
  std::ofstream out(path);
  out << "# mfdem push summary; forces in N, lengths in m, times in s\n"
      << scene::wrap_text(kPushDefinitions, kTextWidth, "# ") << "\n"
      << fmt::format("config = \"{}\"\nseed = {}\nstatus = \"{}\"\nsleeper_vertical = \"{}\"\n", p.config.name,
                     p.config.seed, r.status, sleeper_vertical(r));
  if (!r.message.empty()) out << fmt::format("message = \"\"\"{}\"\"\"\n", r.message);
  out << fmt::format("push_config = \"{}\"\nconfig_hash = \"{}\"\nrevision = \"{}\"\n", r.push_config, r.config_hash,
                     r.revision);
  out << fmt::format(
      "stones = {}\nelements = {}\nvelocity = {:.6g}\ndistance = {:.6g}\npeak_force = {:.6g}\nu_at_peak = {:.6g}\nmean_force = {:.6g}\n"
      "max_contact_force = {:.6g}\ncontact_force_q999 = {:.6g}\nmean_contact_force = {:.6g}\n"
      "peak_base = {:.6g}\npeak_crib = {:.6g}\npeak_shoulder = {:.6g}\npeak_top = {:.6g}\n"
      "start_support_base = {:.6g}\nstart_support_crib = {:.6g}\nstart_support_shoulder = {:.6g}\n"
      "peak_pressing_base = {:.6g}\npeak_pressing_crib = {:.6g}\npeak_pressing_shoulder = {:.6g}\n"
      "max_inertial_number = {:.6g}\nfinal_heave = {:.6g}\ntime_step = {:.6g}\ntime_step_limit = {:.6g}\n"
      "time_step_reason = \"{}\"\nsteps = {}\nwall_seconds = {:.6g}\n",
      r.stones, r.elements, r.velocity, r.distance, r.peak_force, r.u_at_peak, r.mean_force, r.max_contact_force,
      r.contact_force_q999, r.mean_contact_force, r.at_peak().parts.base, r.at_peak().parts.crib,
      r.at_peak().parts.shoulder, r.at_peak().parts.top, r.curve.front().support.base, r.curve.front().support.crib,
      r.curve.front().support.shoulder, r.at_peak().pressing.base, r.at_peak().pressing.crib,
      r.at_peak().pressing.shoulder, r.max_inertial_number, r.final_heave, r.time_step, r.time_step_limit,
      r.time_step_reason, r.steps, r.wall_seconds);
  // Last: a TOML table ends only at the next one, and readers take the push's numbers from the top level.
  out << fmt::format("\n[model]\npolicy = \"{}\"\nconversion_point = \"{}\"\n", r.model.policy, r.model.conversion_point);
  for (const auto& [name, value] : model_numbers(r.model)) out << fmt::format("{} = {:.6g}\n", name, value);
}

void print_push_summary(std::ostream& out, const PushResult& r, const Packing& p) {
  fmt::print(out, "\nPush test: {} (seed {}), {} stones, {} elements, status {}\n", p.config.name, p.config.seed,
             r.stones, r.elements, r.status);
  fmt::print(out, "  {:<38} {:>12}\n", "quantity", "value");
  const auto row = [&](const std::string& name, const std::string& value) { fmt::print(out, "  {:<38} {:>12}\n", name, value); };
  const ModelReport& m = r.model;
  row("model", m.policy);
  if (m.balls > 0) {
    row("  stones as clumps / balls", fmt::format("{} / {}", m.clumps, m.balls));
    row("  ball rolling friction mu_r", fmt::format("{:.3g}", m.rolling_friction));
    row("  ball friction mu", fmt::format("{:.3g}", m.ball_friction));
    row("  elements / as prepared", fmt::format("{} / {} ({:.2f})", m.elements, m.elements_before, m.element_ratio()));
  }
  if (m.resettling) {
    row("  conversion + settling, wall time", scene::format_duration(m.resettling->wall_seconds));
    row("  settled to force ratio", fmt::format("{:.2e}{}", m.resettling->unbalanced_force_ratio,
                                                   !m.resettling->settled           ? " (time limit)"
                                                   : m.resettling->settled_by_creep ? " (settled by creep)"
                                                                                    : ""));
    if (m.resettling->sleeper_base && m.resettling->sleeper_base_start)
      row("  sleeper rose while settling (mm)",
          fmt::format("{:+.3f}", (*m.resettling->sleeper_base - *m.resettling->sleeper_base_start) * 1e3));
  }
  if (r.push_config != p.config.name) row("materials, guards, [push] from", r.push_config);
  row("push velocity (mm/s)", fmt::format("{:.3g}", r.velocity * 1e3));
  row("push distance u_end (mm)", fmt::format("{:.3g}", r.distance * 1e3));
  row("sleeper vertically", sleeper_vertical(r));
  row("peak lateral force (kN)", fmt::format("{:.3f}", r.peak_force * 1e-3));
  row("  at u (mm)", fmt::format("{:.3f}", r.u_at_peak * 1e3));
  const auto share = [&](double part) {
    return fmt::format("{:.3f} ({:.0f} %)", part * 1e-3, r.peak_force > 0.0 ? 100.0 * part / r.peak_force : 0.0);
  };
  row("  base: sleeper bottom (kN)", share(r.at_peak().parts.base));
  row("  crib: sides along the track (kN)", share(r.at_peak().parts.crib));
  row("  shoulder: sleeper ends (kN)", share(r.at_peak().parts.shoulder));
  if (r.at_peak().parts.top != 0.0) row("  top face (kN)", share(r.at_peak().parts.top));
  // Who carries the sleeper's weight: a base that carries less than the weight leaves the rest
  // hanging on the cribs by side friction, and the base friction resists with that much less.
  const double weight = r.sleeper_weight;
  const auto carried = [&](double part) {
    return fmt::format("{:.3f} ({:.0f} %)", part * 1e-3, weight > 0.0 ? 100.0 * part / weight : 0.0);
  };
  row("sleeper weight (kN)", fmt::format("{:.3f}", weight * 1e-3));
  row("  carried by the base at u = 0 (kN)", carried(r.curve.front().support.base));
  row("  by the crib sides at u = 0 (kN)", carried(r.curve.front().support.crib));
  row("  by the base at the peak (kN)", carried(r.at_peak().support.base));
  row("  by the crib sides at the peak (kN)", carried(r.at_peak().support.crib));
  // How far friction is used on the faces where it is the only resistance: mu would be full.
  const auto used = [](double part, double pressing) {
    return pressing > 0.0 ? fmt::format("{:.2f}", part / pressing) : std::string("-");
  };
  row("stone-sleeper friction mu", fmt::format("{:.2f}", r.sleeper_friction));
  row("friction used at the peak: base", used(r.at_peak().parts.base, r.at_peak().pressing.base));
  row("  crib (F part / normal force)", used(r.at_peak().parts.crib, r.at_peak().pressing.crib));
  row("  crib sides pressed with (kN)", fmt::format("{:.3f}", r.at_peak().pressing.crib * 1e-3));
  row("F(u_end) (kN)", fmt::format("{:.3f}", r.curve.back().force * 1e-3));
  row("mean F over the push, work/u_end (kN)", fmt::format("{:.3f}", r.mean_force * 1e-3));
  row("max particle contact force (kN)", fmt::format("{:.3f}", r.max_contact_force * 1e-3));
  row("  99.9 % quantile (kN)", fmt::format("{:.3f}", r.contact_force_q999 * 1e-3));
  row("  mean (N)", fmt::format("{:.1f}", r.mean_contact_force));
  row("sleeper heave at u_end (mm)", fmt::format("{:.3f}", r.final_heave * 1e3));
  row("max inertial number", fmt::format("{:.2e}", r.max_inertial_number));
  row("time step (s)", fmt::format("{:.3g}", r.time_step));
  row("  of the critical step (s)", fmt::format("{:.3g}, set by the {}", r.time_step_limit, r.time_step_reason));
  row("steps", fmt::format("{}", r.steps));
  row("wall time", scene::format_duration(r.wall_seconds));
  fmt::print(out, "{}\n", scene::wrap_text(std::string("Definitions: ") + kPushDefinitions, kTextWidth));
  if (!r.message.empty()) fmt::print(out, "Stopped: {}\n", r.message);
}

RateCheck compare_rates(const PushResult& full, const PushResult& half) {
  const auto change = [](double at_full, double at_half) { return at_full != 0.0 ? (at_half - at_full) / at_full : 0.0; };
  RateCheck c;
  c.velocity = full.velocity;
  c.half_velocity = half.velocity;
  c.peak_change = change(full.peak_force, half.peak_force);
  c.mean_change = change(full.mean_force, half.mean_force);
  c.window_full = window_mean_forces(full.curve, c.window);
  c.window_half = window_mean_forces(half.curve, c.window);
  const std::size_t n = std::min(c.window_full.size(), c.window_half.size());  // a push stopped early has fewer
  c.window_full.resize(n), c.window_half.resize(n);
  for (std::size_t w = 0; w < n; ++w) {
    c.window_change.push_back(change(c.window_full[w], c.window_half[w]));
    if (std::abs(c.window_change.back()) > std::abs(c.largest_window_change))
      c.largest_window_change = c.window_change.back();
  }
  return c;
}

void print_rate_check(std::ostream& out, const PushResult& full, const PushResult& half, const RateCheck& c) {
  fmt::print(out, "\nRate check (quasi-static evidence): the push repeated at half the velocity\n");
  fmt::print(out, "  {:<18} {:>14} {:>14} {:>14} {:>16}\n", "velocity (mm/s)", "peak F (kN)", "mean F (kN)", "max I",
             "q99.9 f (kN)");
  for (const PushResult* r : {&full, &half})
    fmt::print(out, "  {:<18.4g} {:>14.3f} {:>14.3f} {:>14.2e} {:>16.3f}\n", r->velocity * 1e3, r->peak_force * 1e-3,
               r->mean_force * 1e-3, r->max_inertial_number, r->contact_force_q999 * 1e-3);
  fmt::print(out, "  mean F over each {:.3g} mm of u (kN):\n  {:<18}", c.window * 1e3, "u (mm)");
  const double u_end = std::min(full.curve.empty() ? 0.0 : full.curve.back().u,
                                half.curve.empty() ? 0.0 : half.curve.back().u);
  for (std::size_t w = 0; w < c.window_change.size(); ++w)
    fmt::print(out, " {:>9}", fmt::format("{:.3g}-{:.3g}", w * c.window * 1e3,
                                          std::min((w + 1) * c.window, u_end) * 1e3));
  const auto window_row = [&](const char* name, const std::vector<double>& values, double scale, const char* format) {
    fmt::print(out, "\n  {:<18}", name);
    for (double v : values) fmt::print(out, " {:>9}", fmt::format(fmt::runtime(format), v * scale));
  };
  window_row(fmt::format("{:.4g}", full.velocity * 1e3).c_str(), c.window_full, 1e-3, "{:.3f}");
  window_row(fmt::format("{:.4g}", half.velocity * 1e3).c_str(), c.window_half, 1e-3, "{:.3f}");
  window_row("change (%)", c.window_change, 100.0, "{:+.2f}");
  fmt::print(out, "\n  change of the peak force at half the velocity: {:+.2f} % ({} the {:.0f} % criterion)\n",
             100.0 * c.peak_change, c.within_criterion() ? "within" : "OUTSIDE",
             100.0 * kRateCriterion);
  fmt::print(out, "  change of the mean force (work / u_end): {:+.2f} %\n", 100.0 * c.mean_change);
  fmt::print(out, "  largest change of a {:.3g} mm window mean: {:+.2f} %\n", c.window * 1e3,
             100.0 * c.largest_window_change);
}

void write_rate_check(const std::filesystem::path& path, const RateCheck& c) {
  std::ofstream out(path);
  const auto list = [](const std::vector<double>& values) {
    std::string text;
    for (double v : values) text += (text.empty() ? "" : ", ") + fmt::format("{:.6g}", v);
    return "[" + text + "]";
  };
  out << "# mfdem push --check-rate: the push repeated at half the velocity; forces in N, velocities in m/s,\n"
      << "# changes as fractions, (half - full) / full; windows: mean F over consecutive windows of u\n"
      << fmt::format("velocity = {:.6g}\nhalf_velocity = {:.6g}\npeak_change = {:.6g}\ncriterion = {:.6g}\n"
                     "within_criterion = {}\nmean_change = {:.6g}\nwindow = {:.6g}\nlargest_window_change = {:.6g}\n",
                     c.velocity, c.half_velocity, c.peak_change, kRateCriterion,
                     c.within_criterion(), c.mean_change, c.window, c.largest_window_change)
      << "window_mean_force = " << list(c.window_full) << "\n"
      << "window_mean_force_half = " << list(c.window_half) << "\n"
      << "window_change = " << list(c.window_change) << "\n";
}

}  // namespace mfdem::railway
