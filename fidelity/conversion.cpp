#include "fidelity/conversion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "dem/neighbor_list.hpp"

namespace mfdem::fidelity {
namespace {

constexpr double kSolidSphereInertia = 0.4;  // I = 2/5 m r^2

// Distance from x to the nearest point of the box (0 inside), m.
double distance_to_box(const dem::Vec3& x, const dem::RigidBox& box, const dem::Domain& domain) {
  const dem::Vec3 local = domain.nearest_image(x - box.centre);
  const dem::Vec3 outside = (local.cwiseAbs() - box.half_extent).cwiseMax(0.0);
  return outside.norm();
}

bool is_centred_sphere(const dem::ClumpSpec& c) {
  return c.pebbles.size() == 1 && c.pebbles.front().offset == dem::Vec3::Zero();
}

}  // namespace

StoneGeometry measure_stone(const dem::ClumpSpec& stone, const BedFrame& frame) {
  StoneGeometry g;
  g.height = stone.position.z() - frame.floor_height;
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& p : stone.pebbles) {
    const dem::Vec3 x = stone.position + stone.orientation.normalized() * p.offset;
    gap = std::min(gap, distance_to_box(x, frame.sleeper, frame.domain) - p.radius);
  }
  g.sleeper_gap = std::max(0.0, gap);
  return g;
}

dem::ClumpSpec ball_of(const dem::ClumpSpec& clump, double density, int material) {
  dem::ClumpSpec ball = clump;
  ball.material = material;
  if (is_centred_sphere(clump)) return ball;
  const double radius = std::cbrt(3.0 * clump.mass / (4.0 * std::numbers::pi * density));
  ball.pebbles = {dem::Pebble{dem::Vec3::Zero(), radius}};
  ball.principal_inertia = dem::Vec3::Constant(kSolidSphereInertia * clump.mass * radius * radius);
  return ball;
}

ConvertedBed convert_bed(const std::vector<dem::ClumpSpec>& bodies, const std::vector<dem::SpringState>& springs,
                         const Policy& policy, const BedFrame& frame, double density, int ball_material) {
  ConvertedBed out;
  out.bodies.reserve(bodies.size());
  // Old and new first element of every body.
  std::vector<std::int64_t> old_first(bodies.size() + 1, 0), new_first(bodies.size() + 1, 0);
  std::vector<std::int64_t> body_of_element;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const dem::ClumpSpec& stone = bodies[b];
    const bool already_ball = stone.material == ball_material;
    const bool to_ball = !already_ball && policy.choose(measure_stone(stone, frame)) == Representation::ball;
    out.bodies.push_back(to_ball ? ball_of(stone, density, ball_material) : stone);
    out.reshaped.push_back(to_ball && !is_centred_sphere(stone));  // a centred one-pebble clump keeps its geometry
    out.converted += to_ball;
    (already_ball || to_ball ? out.balls : out.clumps) += 1;
    old_first[b + 1] = old_first[b] + static_cast<std::int64_t>(stone.pebbles.size());
    new_first[b + 1] = new_first[b] + static_cast<std::int64_t>(out.bodies.back().pebbles.size());
    body_of_element.insert(body_of_element.end(), stone.pebbles.size(), static_cast<std::int64_t>(b));
  }
  out.elements_before = old_first.back();
  out.elements_after = new_first.back();
  const auto renumber = [&](dem::Index element, dem::Index& to) {
    if (element < 0 || element >= old_first.back()) return false;
    const std::int64_t b = body_of_element[element];
    if (out.reshaped[b]) return false;
    to = static_cast<dem::Index>(new_first[b] + (element - old_first[b]));
    return true;
  };
  for (const dem::SpringState& s : springs) {
    dem::SpringState moved = s;
    bool kept = renumber(s.first, moved.first);
    if (kept && s.kind == dem::SpringState::Kind::kPair) kept = renumber(s.second, moved.second);
    if (kept) out.springs.push_back(moved);
    else ++out.springs_dropped;
  }
  return out;
}

std::vector<double> fitting_radii(const ConvertedBed& bed, const dem::Domain& domain,
                                  const std::vector<dem::PlaneWall>& walls, const std::vector<dem::RigidBox>& boxes,
                                  double smallest_fraction) {
  dem::Elements e;
  std::vector<double> radius;
  for (std::size_t b = 0; b < bed.bodies.size(); ++b) {
    const dem::ClumpSpec& c = bed.bodies[b];
    radius.push_back(c.pebbles.front().radius);
    for (const auto& p : c.pebbles) {
      e.position.push_back(c.position + c.orientation.normalized() * p.offset);
      e.offset.push_back(p.offset);
      e.radius.push_back(p.radius);
      e.material.push_back(c.material);
      e.body.push_back(static_cast<dem::Index>(b));
    }
  }
  std::vector<double> fit(bed.bodies.size());
  for (std::size_t b = 0; b < bed.bodies.size(); ++b) {
    fit[b] = radius[b];
    if (!bed.reshaped[b]) continue;
    const dem::Vec3& x = bed.bodies[b].position;
    for (const auto& w : walls) fit[b] = std::min(fit[b], (x - w.point).dot(w.normal));
    for (const auto& box : boxes) fit[b] = std::min(fit[b], distance_to_box(x, box, domain));
  }
  // Every overlapping pair at the full radii (no skin): the only neighbours that constrain.
  const dem::PairList pairs = dem::build_pair_list(e, domain, 0.0);
  const dem::Vec3 length = domain.length();
  for (dem::Index p = 0; p < pairs.size(); ++p) {
    const dem::Index i = pairs.first[p], j = pairs.second[p];
    const auto bi = static_cast<std::size_t>(e.body[i]), bj = static_cast<std::size_t>(e.body[j]);
    if (!bed.reshaped[bi] && !bed.reshaped[bj]) continue;
    const double distance = (e.position[j] + dem::image_shift(pairs.image[p], length) - e.position[i]).norm();
    if (bed.reshaped[bi] && bed.reshaped[bj]) {
      const double share = distance / (e.radius[i] + e.radius[j]);
      fit[bi] = std::min(fit[bi], share * e.radius[i]);
      fit[bj] = std::min(fit[bj], share * e.radius[j]);
    } else if (bed.reshaped[bi]) {
      fit[bi] = std::min(fit[bi], distance - e.radius[j]);
    } else {
      fit[bj] = std::min(fit[bj], distance - e.radius[i]);
    }
  }
  for (std::size_t b = 0; b < fit.size(); ++b) fit[b] = std::max(fit[b], smallest_fraction * radius[b]);
  return fit;
}

}  // namespace mfdem::fidelity
