// Stability guards (dem/stability.hpp): a NaN, an overlap beyond the allowed fraction of a radius
// and a growth of the energy balance each stop the run with a StabilityError that says what
// happened, to which body, at which time and step; the last good state is kept. Through the
// real `mfdem run`, such a stop exits with status 3 and keeps the frames on disk.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "dem/state_file.hpp"
#include "studies/scene/scene_file.hpp"
#include "tests/dem/builders.hpp"
#include "tests/support/run_mfdem.hpp"

namespace {

using Catch::Matchers::Contains;
using mfdem::dem::Simulation;
using mfdem::dem::StabilityError;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

constexpr double kRadius = 0.01;  // m

// 64 spheres on a lattice 0.5 % tighter than their diameter in a closed box: every sphere starts
// in contact with its neighbours (overlap 0.1 mm), so a NaN cannot stay alone.
Simulation dense_box() {
  MaterialParameters grain;
  grain.rolling_friction = 0.3;
  grain.damping_ratio = 0.3;
  MaterialParameters wall = grain;
  wall.name = "wall";
  const double pitch = 2.0 * kRadius * 0.995, edge = 4 * pitch;
  Simulation sim(box_domain(Vec3::Zero(), Vec3::Constant(edge)), material_table({grain, wall}),
                 settings(Vec3(0, 0, -kGravity)));
  for (const auto& s : lattice({4, 4, 4}, Vec3::Zero(), pitch, kRadius, kRadius, 0.0, 3)) sim.add_sphere(s);
  for (const auto& w : mfdem::dem::box_walls("box", Vec3::Zero(), Vec3::Constant(edge), false, 1)) sim.add_wall(w);
  sim.prepare();
  return sim;
}

// Steps until a StabilityError (returning its message) or `steps` steps (returning "").
std::string run_until_error(Simulation& sim, int steps) {
  try {
    for (int k = 0; k < steps; ++k) sim.step();
  } catch (const StabilityError& e) {
    return e.what();
  }
  return "";
}

// Four ballast-sized spheres: three on a floor, one falling onto them from 7 mm above; the
// [simulation] keys (duration, step, output interval) and the guards' keys are written in.
std::string four_spheres(const std::string& simulation_keys, const std::string& guards) {
  return "# a scene made unstable on purpose: its time step is above the stability limit\n"
         "[simulation]\n" +
         simulation_keys + "[guards]\n" + guards +
         "[domain]\n"
         "min = [-0.5, -0.5, 0.0]\n"
         "max = [0.5, 0.5, 1.0]\n"
         "[materials.ballast]\n"
         "density = 2800.0\n"
         "normal_stiffness = 2e7\n"
         "shear_stiffness = 2e7\n"
         "friction = 0.5\n"
         "[[sphere]]\nposition = [0.0, 0.0, 0.05]\nradius = 0.05\nmaterial = \"ballast\"\n"
         "[[sphere]]\nposition = [0.1, 0.0, 0.05]\nradius = 0.05\nmaterial = \"ballast\"\n"
         "[[sphere]]\nposition = [0.05, 0.09, 0.05]\nradius = 0.05\nmaterial = \"ballast\"\n"
         "[[sphere]]\nposition = [0.05, 0.03, 0.14]\nradius = 0.05\nmaterial = \"ballast\"\n"
         "[[wall]]\ntype = \"plane\"\nname = \"floor\"\npoint = [0.0, 0.0, 0.0]\n"
         "normal = [0.0, 0.0, 1.0]\nmaterial = \"ballast\"\n";
}

double stability_limit_of(const std::filesystem::path& scene) {
  Simulation probe = mfdem::scene::make_simulation(mfdem::scene::load_scene(scene));
  probe.prepare();
  return probe.time_step_limit().limit;
}

}  // namespace

TEST_CASE("a NaN velocity stops the run at the next step, naming the body", "[dem][guards]") {
  // Body 21 is inside the lattice (index 1 + 4 + 16): it touches six neighbours, three of them
  // with lower indices, which the NaN reaches through the contact forces in the same step.
  Simulation sim = dense_box();
  REQUIRE(run_until_error(sim, 50).empty());
  constexpr int victim = 21;
  const std::int64_t step = sim.step_count();
  sim.mutable_bodies().velocity[victim].x() = std::numeric_limits<double>::quiet_NaN();
  const std::string message = run_until_error(sim, 1);
  CAPTURE(message);
  CHECK_THAT(message, Contains("body 21 has a non-finite position or velocity"));
  CHECK_THAT(message, Contains(fmt::format("(step {})", step + 1)));
  CHECK_THAT(message, Contains("unstable run at t = "));
  REQUIRE(sim.last_good_state().has_value());
  CHECK(all_finite(sim.last_good_state()->velocity));
}

TEST_CASE("an overlap beyond the allowed fraction of a radius stops the run", "[dem][guards]") {
  // Soft springs and a hard impact: two spheres meeting head-on at 2 x 5 m/s with a contact
  // stiffness of 1e4 N/m would overlap by v / w = 7.7 mm (w = sqrt(kn / m_eff) = 1306 rad/s),
  // beyond 0.5 R = 5 mm; a sphere hitting the floor at 10 m/s would overlap by 10.8 mm.
  MaterialParameters soft;
  soft.stiffness = 2e4;
  Simulation pair(box_domain(Vec3::Constant(-0.1), Vec3::Constant(0.1)), material_table({soft}),
                  settings(Vec3::Zero()));
  pair.add_sphere(sphere(Vec3(-0.011, 0, 0), kRadius, 0, Vec3(5, 0, 0)));
  pair.add_sphere(sphere(Vec3(0.011, 0, 0), kRadius, 0, Vec3(-5, 0, 0)));
  pair.prepare();
  std::string message = run_until_error(pair, 10000);
  CAPTURE(message);
  CHECK_THAT(message, Contains("), body 0: overlap between bodies 0 and 1 exceeds 0.5 of the smaller radius"));
  // When: the 2 mm gap closes at 10 m/s, then the overlap reaches 0.5 R after
  // asin(0.5 R w / v) / w. The guard trips in the step that crosses it (time() is the last
  // completed step); the contact starts within a step of the gap closing: tolerance one step.
  const double w = std::sqrt(0.5 * soft.stiffness / (0.5 * sphere_mass(kRadius)));
  const double expected = 0.002 / 10.0 + std::asin(0.5 * kRadius * w / 10.0) / w;
  CAPTURE(pair.time(), pair.time_step(), expected);
  CHECK(std::abs(pair.time() + 0.5 * pair.time_step() - expected) <= pair.time_step());
  CHECK_THAT(message, Contains(fmt::format("(step {})", pair.step_count() + 1)));

  Simulation drop(box_domain(Vec3(-0.1, -0.1, 0), Vec3(0.1, 0.1, 0.2)), material_table({soft}),
                  settings(Vec3::Zero()));
  drop.add_sphere(sphere(Vec3(0, 0, 0.011), kRadius, 0, Vec3(0, 0, -10)));
  drop.add_wall(floor_wall(0));
  drop.prepare();
  message = run_until_error(drop, 10000);
  CAPTURE(message);
  CHECK_THAT(message, Contains("body 0 overlaps a wall by more than 0.5 of its radius"));
}

TEST_CASE("energy put in without work stops the run at the next energy check, naming the fastest body",
          "[dem][guards]") {
  // Three spheres flying apart in empty space: nothing should change the energy balance. At step
  // 100 body 2 is sped up behind the solver's back (2 m/s to 4 m/s: the kinetic energy grows
  // by far more than the allowed 5 % of the energy scale); the check at step 200 catches it.
  Simulation sim(box_domain(Vec3::Constant(-1), Vec3::Constant(1)), material_table({MaterialParameters{}}),
                 settings(Vec3::Zero()));
  sim.add_sphere(sphere(Vec3(-0.5, 0, 0), kRadius, 0, Vec3(-1, 0, 0)));
  sim.add_sphere(sphere(Vec3(0.0, 0, 0), kRadius, 0, Vec3(0, 1, 0)));
  sim.add_sphere(sphere(Vec3(0.5, 0, 0), kRadius, 0, Vec3(2, 0, 0)));
  sim.prepare();
  REQUIRE(sim.settings().guards.check_interval == 200);
  REQUIRE(run_until_error(sim, 100).empty());
  sim.mutable_bodies().velocity[2] *= 2.0;
  const std::string message = run_until_error(sim, 1000);
  CAPTURE(message);
  // The check runs after step 200 has completed: the message names step 200 and its time.
  CHECK_THAT(message, Contains("energy grew by") && Contains("fastest is body 2 at 4 m/s") &&
                          Contains("(step 200), body 2"));
  CHECK_THAT(message, Contains(fmt::format("at t = {:.6g} s", sim.time())));
  CHECK(sim.step_count() == 200);
  REQUIRE(sim.last_good_state().has_value());
  CHECK(sim.last_good_state()->time == 0.0);  // the state at prepare(); no check has passed since
  CHECK(sim.last_good_state()->velocity[2] == Vec3(2, 0, 0));
}

TEST_CASE("mfdem run stops an unstable forced step with status 3 and keeps the frames and the last good state",
          "[dem][guards][cli]") {
  const mfdem::test::TempDir dir;
  auto scene_text = [](const std::string& time_step) { return four_spheres("duration = 0.2\n" + time_step, "check_interval = 1\n"); };
  // The limit of this scene, from the solver itself.
  const auto probe_file = dir.write("probe.toml", scene_text("output_interval = 0.002\n"));
  const double limit = stability_limit_of(probe_file);
  const auto scene = dir.write("unstable.toml",
                               scene_text(fmt::format("time_step = {0:.17g}\noutput_interval = {0:.17g}\n",
                                                      2.0 * limit)));

  // Without --force-dt the step is refused before anything runs (status 2, config error).
  const auto refused = mfdem::test::run_mfdem({"run", scene.string(), "--out", (dir.path() / "refused").string(), "--quiet"});
  CHECK(refused.status == 2);
  CHECK_THAT(refused.err, Contains("above the stability limit"));

  const auto out = dir.path() / "out";
  const auto result = mfdem::test::run_mfdem({"run", scene.string(), "--out", out.string(), "--force-dt", "--quiet"});
  CAPTURE(result.out, result.err);
  CHECK(result.status == 3);
  CHECK_THAT(result.err, Contains("mfdem: error: unstable run at t = ") && Contains("(step ") &&
                             Contains("), body ") && Contains("The last good state"));

  const auto state = out / "state.h5";
  const int frames = mfdem::dem::count_frames(state);
  REQUIRE(frames >= 3);  // the initial frame, at least one output frame, the last good state
  const auto last = mfdem::dem::read_frame(state, frames - 1);
  CHECK(last.label == "last good state");
  CHECK(mfdem::dem::read_frame(state, 0).label.empty());
  CHECK(last.position.size() == 4);
  CHECK(all_finite(last.position));
  CHECK(all_finite(last.velocity));
  CHECK(all_finite(last.angular_velocity));
  // The last good state is the state after the last step whose check passed (a check every
  // step here), written as a frame by then (output every step): the step before the one the
  // message names, with the same positions. At twice the limit the falling sphere's impact
  // excites modes that grow by |lambda| = 13.9 per step: the run stops within a step or two of
  // it (at step 75 of 0.58 ms), well after the start.
  const auto at = result.err.find("(step ");
  REQUIRE(at != std::string::npos);
  const long long failed_step = std::stoll(result.err.substr(at + 6));
  CAPTURE(last.step, last.time, frames, failed_step);
  CHECK(last.step == failed_step - 1);
  CHECK(last.step > 0);
  bool matched = false;
  for (int f = 0; f < frames - 1 && !matched; ++f) {
    const auto frame = mfdem::dem::read_frame(state, f);
    if (frame.step != last.step) continue;
    matched = true;
    CHECK(frame.time == last.time);
    CHECK(frame.position == last.position);
    CHECK(frame.velocity == last.velocity);
  }
  CHECK(matched);
}

TEST_CASE("a run ends with an energy check: a blow-up between two checks is not reported finished",
          "[dem][guards][cli]") {
  // 100 steps at 3.7 times the limit with the default check every 200 steps: before the guard
  // ran at the end too, this run was written "finished" (exit 0).
  const mfdem::test::TempDir dir;
  const double limit =
      stability_limit_of(dir.write("probe.toml", four_spheres("duration = 0.2\noutput_interval = 0.002\n", "")));
  const double step = 3.7 * limit;
  const auto scene = dir.write("short.toml", four_spheres(fmt::format("duration = {1:.17g}\ntime_step = {0:.17g}\n"
                                                                      "force_time_step = true\n",
                                                                      step, 100 * step),
                                                          ""));
  const auto result = mfdem::test::run_mfdem({"run", scene.string(), "--out", (dir.path() / "out").string(), "-q"});
  CAPTURE(result.err);
  CHECK(result.status == 3);
  CHECK_THAT(result.err, Contains("energy grew") && Contains("(step 100)"));  // found by the check at the end
  std::stringstream summary;
  summary << std::ifstream(dir.path() / "out" / "summary.toml").rdbuf();
  CHECK_THAT(summary.str(), Contains("status = \"unstable\""));
}

TEST_CASE("bodies a scene places overlapping beyond the guard are refused before any step, naming them",
          "[dem][guards][cli]") {
  const mfdem::test::TempDir dir;
  std::string text = four_spheres("duration = 0.2\noutput_interval = 0.002\n", "");
  text += "[[sphere]]\nposition = [0.0, 0.0, 0.06]\nradius = 0.05\nmaterial = \"ballast\"\n";  // 10 mm from body 0
  const auto scene = dir.write("overlap.toml", text);
  const auto result = mfdem::test::run_mfdem({"run", scene.string(), "--out", (dir.path() / "out").string(), "-q"});
  CHECK(result.status == 2);
  CHECK_THAT(result.err, Contains("overlap.toml") && Contains("bodies 0 and 4") && Contains("before any step"));
  const auto check = mfdem::test::run_mfdem({"check", scene.string()});
  CHECK(check.status == 2);
  CHECK_THAT(check.err, Contains("bodies 0 and 4"));
}

TEST_CASE("a duration that makes more steps than a run can count is refused, naming the key", "[dem][guards][cli]") {
  const mfdem::test::TempDir dir;
  const std::string text = four_spheres("duration = 0.2\ntime_step = 1e-300\noutput_interval = 0.002\n", "");
  const auto scene = dir.write("tiny_step.toml", text);
  const auto result = mfdem::test::run_mfdem({"run", scene.string(), "--out", (dir.path() / "out").string(), "-q"});
  CHECK(result.status == 2);
  CHECK_THAT(result.err, Contains("tiny_step.toml") && Contains("duration = 0.2") && Contains("steps"));
}
