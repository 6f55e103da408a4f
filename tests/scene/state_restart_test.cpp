// A scene can start from a frame of an earlier run's state.h5: the normal way to reuse a
// settled packing.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "dem/state_file.hpp"
#include "studies/scene/scene_file.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;

namespace {

// A scene of one ballast material whose bodies all come from state.h5 beside it ([[state_file]]
// on line 13), in the domain [0, domain_max].
void write_restart_scene(const std::filesystem::path& file, const std::string& domain_max) {
  std::ofstream(file) << "\n[simulation]\nduration = 0.01\n[domain]\nmin = [0, 0, 0]\nmax = " << domain_max
                      << "\n[materials.ballast]\ndensity = 2800.0\nnormal_stiffness = 2e7\nshear_stiffness = 2e7\n"
                         "friction = 0.5\n[[state_file]]\npath = \"state.h5\"\n";
}

}  // namespace

TEST_CASE("a scene restarted from a saved frame holds exactly the saved bodies", "[scene][restart]") {
  // Reference: the saved frame itself. Positions, velocities, orientations, masses, inertias
  // and pebbles must come back bitwise (HDF5 stores doubles exactly).
  test::TempDir dir;
  const auto original = dir.path() / "pour.toml";
  std::ofstream(original) << R"(
[simulation]
duration = 0.01
seed = 3
[domain]
min = [0, 0, 0]
max = [0.4, 0.4, 0.8]
[materials.ballast]
density = 2800.0
normal_stiffness = 2e7
shear_stiffness = 2e7
friction = 0.5
[[stone_group]]
min = [0, 0, 0.05]
max = [0.4, 0.4, 0.8]
count = 20
material = "ballast"
random_speed = 0.3
[[sphere]]
position = [0.2, 0.2, 0.7]
radius = 0.02
material = "ballast"
angular_velocity = [1, 2, 3]
[[wall]]
type = "box"
min = [0, 0, 0]
max = [0.4, 0.4, 0.8]
material = "ballast"
)";
  const scene::Scene first = scene::load_scene(original);
  dem::Simulation sim = scene::make_simulation(first);
  sim.prepare();
  for (int k = 0; k < 300; ++k) sim.step();
  {
    dem::StateFile state(dir.path() / "state.h5", sim, "test");
    state.write_frame(sim);
  }
  const auto restart = dir.path() / "restart.toml";
  write_restart_scene(restart, "[0.4, 0.4, 0.8]");
  const scene::Scene second = scene::load_scene(restart);
  dem::Simulation again = scene::make_simulation(second);
  const dem::Bodies& a = sim.bodies();
  const dem::Bodies& b = again.bodies();
  REQUIRE(b.size() == a.size());
  CHECK(b.position == a.position);
  CHECK(b.velocity == a.velocity);
  CHECK(b.angular_velocity == a.angular_velocity);
  CHECK(b.mass == a.mass);
  CHECK(b.inertia == a.inertia);
  CHECK(again.elements().offset == sim.elements().offset);
  CHECK(again.elements().radius == sim.elements().radius);
  for (dem::Index k = 0; k < a.size(); ++k) CHECK(b.orientation[k].coeffs() == a.orientation[k].coeffs());
}

TEST_CASE("a state file with a material the scene lacks is refused by name", "[scene][restart]") {
  test::TempDir dir;
  dem::MaterialTable materials;
  dem::Material granite;
  granite.name = "granite";
  materials.add(granite);
  dem::Simulation sim(dem::Domain{}, materials, dem::SimulationSettings{});
  dem::SphereSpec s;
  s.position = dem::Vec3(0.5, 0.5, 0.5);
  sim.add_sphere(s);
  {
    dem::StateFile state(dir.path() / "state.h5", sim, "test");
    state.write_frame(sim);
  }
  const auto scene_file = dir.path() / "restart.toml";
  write_restart_scene(scene_file, "[1, 1, 1]");
  CHECK_THROWS_WITH(scene::load_scene(scene_file), Catch::Contains("material 'granite'") &&
                                                       Catch::Contains("restart.toml:13"));
}

TEST_CASE("a state file with a NaN position or a zero mass is refused naming the file, the body and the value",
          "[scene][restart]") {
  test::TempDir dir;
  dem::MaterialTable materials;
  dem::Material ballast;
  ballast.name = "ballast";
  materials.add(ballast);
  const auto scene_file = dir.path() / "restart.toml";
  write_restart_scene(scene_file, "[1, 1, 1]");
  const auto write_state = [&](const dem::Vec3& position, double mass = -1.0) {
    dem::Simulation sim(dem::Domain{}, materials, dem::SimulationSettings{});
    dem::SphereSpec s;
    s.position = dem::Vec3(0.5, 0.5, 0.5);
    sim.add_sphere(s);
    s.position = dem::Vec3(0.2, 0.5, 0.5);
    sim.add_sphere(s);
    sim.mutable_bodies().position[1] = position;  // as a damaged or hand-edited file holds it
    if (mass >= 0.0) sim.mutable_bodies().mass[1] = mass;
    dem::StateFile state(dir.path() / "state.h5", sim, "test");
    state.write_frame(sim);
  };
  write_state(dem::Vec3(0.2, std::nan(""), 0.5));
  CHECK_THROWS_WITH(scene::load_scene(scene_file), Catch::Contains("state.h5") && Catch::Contains("body 1") &&
                                                       Catch::Contains("nan") && Catch::Contains("finite positions"));
  write_state(dem::Vec3(0.2, 0.5, 0.5), 0.0);
  CHECK_THROWS_WITH(scene::load_scene(scene_file), Catch::Contains("state.h5") && Catch::Contains("body 1") &&
                                                       Catch::Contains("mass 0 kg"));
  write_state(dem::Vec3(0.2, 0.5, 0.5));
  CHECK_NOTHROW(scene::load_scene(scene_file));
}
