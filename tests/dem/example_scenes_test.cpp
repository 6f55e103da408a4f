// The commented example scenes in studies/scenes/examples/ load, pass prepare() (time step within
// the limit) and run; the two small ones are run to the end and give the numbers their comments
// promise. So the examples never rot when the scene format or the solver changes.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "studies/scene/scene_file.hpp"
#include "tests/dem/builders.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;

std::filesystem::path example(const std::string& name) {
  return std::filesystem::path(MFDEM_SOURCE_DIR) / "studies" / "scenes" / "examples" / name;
}

// Runs the scene to its duration (or `steps` steps if given).
void run(Simulation& sim, double duration, long long steps = -1) {
  const long long total = steps >= 0 ? steps : std::llround(duration / sim.time_step());
  for (long long k = 0; k < total; ++k) sim.step();
}

}  // namespace

TEST_CASE("every example scene loads, prepares and runs", "[dem][examples]") {
  const std::string name = GENERATE("rolling_sphere.toml", "incline.toml", "periodic_shear_box.toml",
                                    "pour_box.toml");
  CAPTURE(name);
  const auto scene = mfdem::scene::load_scene(example(name));
  Simulation sim = mfdem::scene::make_simulation(scene);
  REQUIRE_NOTHROW(sim.prepare());
  CHECK(sim.time_step() <= sim.time_step_limit().limit);
  REQUIRE_NOTHROW(run(sim, scene.duration, 200));
  CHECK(mfdem::dem_test::all_finite(sim.bodies().position));
}

TEST_CASE("the example scenes hold what their comments say", "[dem][examples]") {
  SECTION("rolling_sphere.toml: stops after v0^2 / (2 * 5/7 * mu_r * g) = 0.178 m at 0.71 s") {
    const auto scene = mfdem::scene::load_scene(example("rolling_sphere.toml"));
    REQUIRE(scene.spheres.size() == 1);
    CHECK(scene.spheres[0].angular_velocity.y() * scene.spheres[0].radius == scene.spheres[0].velocity.x());
    Simulation sim = mfdem::scene::make_simulation(scene);
    sim.prepare();
    run(sim, scene.duration);
    // Tolerance 1 mm: the comment quotes three digits.
    CHECK(sim.bodies().position[0].x() == Approx(0.178).margin(1e-3));
    CHECK(std::abs(sim.bodies().velocity[0].x()) < 1e-3);
  }
  SECTION("incline.toml: tan th = 0.2; the sticky sphere rests, the other rolls 0.34 m in 1 s") {
    const auto scene = mfdem::scene::load_scene(example("incline.toml"));
    const Vec3 g = scene.settings.gravity;
    CHECK(g.x() / -g.z() == Approx(0.2).epsilon(1e-5));
    CHECK(g.norm() == Approx(9.81).epsilon(1e-5));
    Simulation sim = mfdem::scene::make_simulation(scene);
    sim.prepare();
    run(sim, scene.duration);
    CHECK(std::abs(sim.bodies().position[0].x()) < 1e-6);
    // a t^2 / 2 = 0.687 / 2 m; the comment quotes 0.34 m.
    CHECK(sim.bodies().position[1].x() == Approx(0.344).margin(5e-3));
  }
  SECTION("periodic_shear_box.toml: periodic along x and y, 240 spheres, a sliding plate") {
    const auto scene = mfdem::scene::load_scene(example("periodic_shear_box.toml"));
    CHECK(scene.domain.periodic == std::array<bool, 3>{true, true, false});
    CHECK(scene.spheres.size() == 240);
    REQUIRE(scene.walls.size() == 1);
    CHECK(scene.walls[0].velocity == Vec3(0.1, 0, 0));
  }
  SECTION("pour_box.toml: 500 spheres with mu_r = 0.3 into an open box of five walls") {
    const auto scene = mfdem::scene::load_scene(example("pour_box.toml"));
    CHECK(scene.spheres.size() == 500);
    CHECK(scene.walls.size() == 5);
    CHECK(scene.walls[4].name == "box.z-");
    const int ballast = scene.materials.index_of("ballast");
    CHECK(scene.materials.pair(ballast, ballast).rolling_friction == 0.3);
    CHECK(scene.materials.pair(ballast, scene.materials.index_of("wall")).rolling_friction == 0.0);
  }
}
