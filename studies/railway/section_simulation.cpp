#include "studies/railway/section_simulation.hpp"

#include <algorithm>

namespace mfdem::railway {
namespace {

dem::PlaneWall plane(const char* name, const dem::Vec3& point, const dem::Vec3& normal) {
  dem::PlaneWall w;
  w.name = name;
  w.point = point;
  w.normal = normal;
  w.material = kFloor;
  return w;
}

}  // namespace

dem::Domain section_domain(const PushStudyConfig& c, double top) {
  const SectionGeometry& g = c.geometry;
  // The shoulder may slump beyond the toe: leave half a metre (or the bed's height) of room.
  const double margin = std::max(0.5, g.ballast_top());
  dem::Domain d;
  d.min = dem::Vec3(-g.toe_half_width() - margin, 0.0, -0.05);
  d.max = dem::Vec3(g.toe_half_width() + margin, g.section_length, top);
  d.periodic = {false, g.periodic_along_track, false};
  return d;
}

dem::Simulation make_section_simulation(const PushStudyConfig& c, const dem::Domain& domain,
                                        const std::vector<dem::ClumpSpec>& stones, const StageSetup& stage) {
  dem::MaterialTable materials;
  dem::Material ballast = c.ballast;
  ballast.friction = stage.stone_friction;
  ballast.local_damping = stage.stone_local_damping;
  materials.add(ballast);
  materials.add(c.sleeper);
  materials.add(c.floor);
  const bool any_ball = std::any_of(stones.begin(), stones.end(), [](const dem::ClumpSpec& s) { return s.material == kBall; });
  // Only a bed with balls has the ball material: an all-clump run then has no rolling channel at
  // all, bitwise and in cost as before the multi-layer model existed.
  if (any_ball) {
    dem::Material ball = ballast;
    ball.name = "ball";
    ball.rolling_friction = stage.ball_rolling_friction.value_or(c.fidelity.rolling_friction);
    ball.friction = stage.ball_friction.value_or(stage.stone_friction);
    materials.add(ball);
  }
  for (const auto& o : c.pairs)
    if (any_ball || (o.material_a != "ball" && o.material_b != "ball")) materials.add_override(o);
  dem::SimulationSettings settings;
  settings.time_step_safety = c.time_step_safety;
  if (stage.time_step) settings.time_step = *stage.time_step;
  settings.guards = c.guards;
  settings.gravity *= stage.gravity_factor;
  dem::Simulation sim(domain, materials, settings);
  for (dem::ClumpSpec stone : stones) {
    if (stone.material != kBall) stone.material = kBallast;
    sim.add_clump(stone);
  }
  const SectionGeometry& g = c.geometry;
  sim.add_wall(plane("floor", dem::Vec3::Zero(), dem::Vec3::UnitZ()));
  if (!g.periodic_along_track) {
    sim.add_wall(plane("track_wall_front", dem::Vec3::Zero(), dem::Vec3::UnitY()));
    sim.add_wall(plane("track_wall_back", dem::Vec3(0.0, g.section_length, 0.0), -dem::Vec3::UnitY()));
  }
  if (stage.container_walls) {
    sim.add_wall(plane("container_left", dem::Vec3(-g.toe_half_width(), 0.0, 0.0), dem::Vec3::UnitX()));
    sim.add_wall(plane("container_right", dem::Vec3(g.toe_half_width(), 0.0, 0.0), -dem::Vec3::UnitX()));
  }
  if (stage.sleeper) sim.add_box(*stage.sleeper);
  return sim;
}

}  // namespace mfdem::railway
