// [[clump]] places one rigid clump by hand: its mass properties are those of the pebbles' union
// (overlap counted once) and its pebbles land where the offsets, the position and the rotation
// put them.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "studies/config/config.hpp"
#include "studies/scene/scene_file.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;
using Catch::Matchers::Contains;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDensity = 2600.0;

// A scene of material "stone" holding `clump_entry` (lines of a [[clump]] and its pebbles).
std::filesystem::path write_scene(const test::TempDir& dir, const std::string& clump_entry) {
  const auto file = dir.path() / "clump.toml";
  std::ofstream(file) << "[simulation]\nduration = 0.01\n[domain]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
                         "[materials.stone]\ndensity = 2600.0\nnormal_stiffness = 1e7\nshear_stiffness = 1e7\n"
                         "friction = 0.5\n"
                      << clump_entry;
  return file;
}

// Two pebbles of radius r at x = -a and +a, shifted so that the pebble frame's origin sits at
// the first pebble: the union's centroid is at (a, 0, 0) of that frame.
std::string dumbbell(double r, double a, const std::string& placement) {
  return "[[clump]]\nmaterial = \"stone\"\n" + placement + "\n[[clump.pebble]]\noffset = [0, 0, 0]\nradius = " +
         std::to_string(r) + "\n[[clump.pebble]]\noffset = [" + std::to_string(2 * a) + ", 0, 0]\nradius = " +
         std::to_string(r) + "\n";
}

}  // namespace

TEST_CASE("a [[clump]] of two overlapping pebbles has the union's mass and inertia", "[scene][clump]") {
  // Reference: the union of two balls of radius r at +-a is a solid of revolution whose section
  // at x is a disc of radius^2 = r^2 - (|x| - a)^2, so per unit density
  //   V = 2 pi (r^2 (r + a) - (r^3 + a^3) / 3),  I_axis = pi (8 r^5 / 15 + r^4 a - 2 r^2 a^3 / 3 + a^5 / 5),
  // and the transverse moment is integral of pi rho^2 (rho^2 / 4 + x^2) dx, done here in closed form too.
  // Tolerance 1e-4 relative: the union is integrated by quasi-Monte Carlo to 1e-5.
  const double r = 0.02, a = 0.01;  // the pebbles overlap by half a radius each
  test::TempDir dir;
  const auto scene = scene::load_scene(write_scene(dir, dumbbell(r, a, "position = [0.1, 0.2, 0.3]")));
  REQUIRE(scene.clumps.size() == 1);
  const dem::ClumpSpec& c = scene.clumps[0];
  const double volume = 2.0 * kPi * (r * r * (r + a) - (r * r * r + a * a * a) / 3.0);
  const double axial = kPi * (8.0 * std::pow(r, 5) / 15.0 + std::pow(r, 4) * a - 2.0 * r * r * a * a * a / 3.0 +
                              std::pow(a, 5) / 5.0);
  // Transverse: 2 * integral over t = x - a in [-a, r] of pi (r^2 - t^2) ((r^2 - t^2) / 4 + (t + a)^2) dt.
  const auto transverse_primitive = [&](double t) {
    const double r2 = r * r;
    // (r^2 - t^2)(r^2 - t^2)/4 + (r^2 - t^2)(t^2 + 2 a t + a^2), integrated term by term in t.
    return (r2 * r2 * t - 2.0 * r2 * t * t * t / 3.0 + std::pow(t, 5) / 5.0) / 4.0 +
           r2 * (t * t * t / 3.0 + a * t * t + a * a * t) - (std::pow(t, 5) / 5.0 + a * std::pow(t, 4) / 2.0 +
                                                            a * a * t * t * t / 3.0);
  };
  const double transverse = 2.0 * kPi * (transverse_primitive(r) - transverse_primitive(-a));
  CHECK(c.mass == Approx(kDensity * volume).epsilon(1e-4));
  CHECK(volume < 2.0 * 4.0 / 3.0 * kPi * r * r * r * 0.9);  // the overlap is real: not the two balls' sum
  CHECK(c.principal_inertia.x() == Approx(kDensity * axial).epsilon(1e-4));
  CHECK(c.principal_inertia.y() == Approx(kDensity * transverse).epsilon(1e-4));
  CHECK(c.principal_inertia.z() == Approx(kDensity * transverse).epsilon(1e-4));
  // The centre of mass is the pebble frame's centroid moved to the position (no rotation).
  CHECK((c.position - dem::Vec3(0.1 + a, 0.2, 0.3)).norm() < 1e-7);
}

TEST_CASE("a rotated [[clump]] puts each pebble at position + rotation x offset", "[scene][clump]") {
  // Reference: a quarter turn about z maps the offset (2a, 0, 0) to (0, 2a, 0); the world pebble
  // centres are exact to rounding (1e-12 m).
  const double r = 0.02, a = r;  // touching pebbles
  test::TempDir dir;
  const auto scene = scene::load_scene(write_scene(
      dir, dumbbell(r, a, "position = [0.1, 0.2, 0.3]\naxis = [0, 0, 2]\nangle = 1.5707963267948966\n"
                          "velocity = [1, 0, 0]")));
  dem::Simulation sim = scene::make_simulation(scene);
  sim.prepare();
  const dem::Elements& e = sim.elements();
  REQUIRE(e.size() == 2);
  CHECK((e.position[0] - dem::Vec3(0.1, 0.2, 0.3)).norm() < 1e-12);
  CHECK((e.position[1] - dem::Vec3(0.1, 0.2 + 2 * a, 0.3)).norm() < 1e-12);
  CHECK((sim.bodies().velocity[0] - dem::Vec3(1, 0, 0)).norm() == 0.0);
  // Touching (not overlapping) pebbles are summed exactly: 2 balls.
  CHECK(sim.bodies().mass[0] == Approx(2.0 * kDensity * 4.0 / 3.0 * kPi * r * r * r).epsilon(1e-12));
}

TEST_CASE("a [[clump]] is refused naming the key and the value", "[scene][clump][refusal]") {
  test::TempDir dir;
  const auto refused = [&](const std::string& entry) {
    try {
      scene::load_scene(write_scene(dir, entry));
    } catch (const config::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string no_pebbles = refused("[[clump]]\nmaterial = \"stone\"\nposition = [0, 0, 0]\n");
  CHECK_THAT(no_pebbles, Contains("clump.toml") && Contains("clump[0].pebble") && Contains("at least one pebble"));
  const std::string bad_radius = refused(
      "[[clump]]\nmaterial = \"stone\"\nposition = [0, 0, 0]\n[[clump.pebble]]\noffset = [0, 0, 0]\nradius = -0.01\n");
  CHECK_THAT(bad_radius, Contains("clump[0].pebble[0].radius") && Contains("-0.01"));
  const std::string bad_axis = refused(
      "[[clump]]\nmaterial = \"stone\"\nposition = [0, 0, 0]\naxis = [0, 0, 0]\nangle = 1\n"
      "[[clump.pebble]]\noffset = [0, 0, 0]\nradius = 0.01\n");
  CHECK_THAT(bad_axis, Contains("clump[0].axis") && Contains("non-zero"));
  const std::string nan_offset = refused(
      "[[clump]]\nmaterial = \"stone\"\nposition = [0, 0, 0]\n[[clump.pebble]]\noffset = [nan, 0, 0]\nradius = 0.01\n");
  CHECK_THAT(nan_offset, Contains("clump[0].pebble[0].offset") && Contains("finite"));
  const std::string typo = refused(
      "[[clump]]\nmaterial = \"stone\"\nposition = [0, 0, 0]\n[[clump.pebble]]\nofset = [0, 0, 0]\nradius = 0.01\n");
  CHECK_THAT(typo, Contains("offset"));
}
