// HDF5 state file round trip (dem/state_file.hpp): what StateFile writes, read_frame gives back
// bit for bit (HDF5 stores IEEE doubles as they are: tolerance none), and the XDMF companion
// points ParaView at the datasets of every frame.
#include <catch2/catch.hpp>

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dem/state_file.hpp"
#include "tests/dem/builders.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

using mfdem::dem::Simulation;
using mfdem::dem::Vec3;
using namespace mfdem::dem_test;

struct Expected {
  double time;
  long long step;
  std::vector<Vec3> position, velocity, angular_velocity, contact_force, wall_force;
  std::vector<mfdem::dem::Index> body_a, body_b;
};

Expected capture(const Simulation& sim) {
  Expected e{sim.time(), sim.step_count(), sim.bodies().position, sim.bodies().velocity,
             sim.bodies().angular_velocity, {}, {}, {}, {}};
  for (const auto& c : sim.contacts()) {
    e.contact_force.push_back(c.force);
    e.body_a.push_back(c.body_a);
    e.body_b.push_back(c.body_b);
  }
  for (int w = 0; w < static_cast<int>(sim.walls().size()); ++w) e.wall_force.push_back(sim.wall_force(w));
  return e;
}

}  // namespace

TEST_CASE("state frames written to HDF5 read back identically, with an XDMF file that references them",
          "[dem][state_file]") {
  // 27 spheres dropped in a lattice 0.5 % tighter than their diameter into an open box: there
  // are contacts and wall forces in every frame.
  MaterialParameters p;
  p.rolling_friction = 0.3;
  p.damping_ratio = 0.2;
  const double radius = 0.01, pitch = 2 * radius * 0.995, edge = 3 * pitch;
  Simulation sim(box_domain(Vec3::Zero(), Vec3(edge, edge, 0.1)), material_table({p}),
                 settings(Vec3(0, 0, -kGravity)));
  for (const auto& s : lattice({3, 3, 3}, Vec3::Zero(), pitch, radius, radius, 0.2, 5)) sim.add_sphere(s);
  for (const auto& w : mfdem::dem::box_walls("box", Vec3::Zero(), Vec3(edge, edge, 0.1), true, 0)) sim.add_wall(w);
  sim.prepare();

  const mfdem::test::TempDir dir;
  const auto path = dir.path() / "state.h5";
  std::vector<Expected> written;
  {
    mfdem::dem::StateFile file(path, sim, "round trip test");
    for (int f = 0; f < 4; ++f) {
      if (f > 0)
        for (int k = 0; k < 100; ++k) sim.step();
      file.write_frame(sim);
      written.push_back(capture(sim));
    }
    // A kept snapshot (what `mfdem run` writes when a guard trips): its own time and state.
    REQUIRE(sim.last_good_state().has_value());
    file.write_snapshot(sim, *sim.last_good_state(), "last good state");
    CHECK(file.frame_count() == 5);
  }

  REQUIRE(mfdem::dem::count_frames(path) == 5);
  for (int f = 0; f < 4; ++f) {
    const auto frame = mfdem::dem::read_frame(path, f);
    const Expected& e = written[f];
    CAPTURE(f);
    CHECK(frame.time == e.time);
    CHECK(frame.step == e.step);
    CHECK(frame.label.empty());
    CHECK(frame.position == e.position);
    CHECK(frame.velocity == e.velocity);
    CHECK(frame.angular_velocity == e.angular_velocity);
    CHECK(frame.contact_force == e.contact_force);
    CHECK(frame.contact_body_a == e.body_a);
    CHECK(frame.contact_body_b == e.body_b);
    CHECK(frame.wall_force == e.wall_force);
    CHECK(frame.element_radius == sim.elements().radius);
    // Not a vacuous comparison: the frames hold contacts and forces on the walls.
    if (f > 0) {
      CHECK(e.contact_force.size() > 20);
      CHECK(e.wall_force[4].z() < 0.0);  // the floor (z-, index 4 of box_walls) is pushed down
    }
  }
  const auto snapshot = mfdem::dem::read_frame(path, 4);
  CHECK(snapshot.label == "last good state");
  CHECK(snapshot.time == sim.last_good_state()->time);
  CHECK(snapshot.step == sim.last_good_state()->step);
  CHECK(snapshot.position == sim.last_good_state()->position);
  CHECK(snapshot.velocity == sim.last_good_state()->velocity);
  CHECK_THROWS_WITH(mfdem::dem::read_frame(path, 5), Catch::Matchers::Contains("has no frame 5"));

  // The XDMF companion: one temporal grid per frame, each pointing at its datasets in state.h5.
  auto xdmf_path = path;
  xdmf_path.replace_extension(".xdmf");
  REQUIRE(std::filesystem::exists(xdmf_path));
  std::ostringstream text;
  text << std::ifstream(xdmf_path).rdbuf();
  const std::string xdmf = text.str();
  for (int f = 0; f < 5; ++f) {
    CAPTURE(f);
    CHECK_THAT(xdmf, Catch::Matchers::Contains(fmt::format("state.h5:/frames/{:06d}/element_position", f)));
    CHECK_THAT(xdmf, Catch::Matchers::Contains(fmt::format("state.h5:/frames/{:06d}/element_velocity", f)));
    CHECK_THAT(xdmf, Catch::Matchers::Contains(fmt::format("<Time Value=\"{:.9g}\"/>", f < 4 ? written[f].time : snapshot.time)));
  }
  CHECK_THAT(xdmf, Catch::Matchers::Contains("state.h5:/elements/radius"));
  CHECK_THAT(xdmf, Catch::Matchers::Contains("NumberOfElements=\"27\""));

  // Rebuilt from the file alone (after a rename), the companion is the one written while running.
  std::filesystem::remove(xdmf_path);
  mfdem::dem::write_xdmf_companion(path);
  std::ostringstream rebuilt;
  rebuilt << std::ifstream(xdmf_path).rdbuf();
  CHECK(rebuilt.str() == xdmf);
}
