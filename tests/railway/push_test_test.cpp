// The single-sleeper push test end to end on a tiny bed of balls: reproducibility (the same seed
// gives the same bits on 1 and 2 threads; a packing saved and loaded pushes bitwise as the one
// in memory), the shape of F(u), and the packing file's round trip. Tolerances: none (memcmp)
// for the bitwise claims; the physical checks are stated where they are made.
//
// The bed: 25 mm balls (every stone the equal-volume ball of a 25 mm stone, mu_r = 0.3) in a 0.2 m periodic
// section under a 0.3 m x 0.06 m x 0.05 m sleeper; about 1,200 stones kept, so the body loops
// span several chunks (dem/chunked.hpp) and the two threads really split the work.
#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <cstring>

#include "dem/chunked.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/push_test.hpp"
#include "studies/railway/stone_columns.hpp"
#include "tests/railway/tiny_bed.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;

namespace {



railway::PushStudyConfig tiny_config() { return railway::parse_push_config(mfdem::test::kTinyBed, "tiny.toml"); }

railway::Packing pack_with(int threads) {
  const int previous = omp_get_max_threads();
  omp_set_num_threads(threads);
  railway::PreparationReport report;
  railway::Packing p = railway::prepare_bed(tiny_config(), true, report);
  omp_set_num_threads(previous);
  return p;
}

railway::PushResult push_with(const railway::Packing& p, int threads) {
  const int previous = omp_get_max_threads();
  omp_set_num_threads(threads);
  railway::PushRun run;
  run.velocity = p.config.push.velocity;
  run.distance = p.config.push.distance;
  run.quiet = true;
  railway::PushResult r = railway::run_push(p, p.config, run);
  omp_set_num_threads(previous);
  return r;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

std::vector<dem::Vec3> positions(const railway::Packing& p) {
  std::vector<dem::Vec3> out;
  for (const auto& b : p.bodies) out.push_back(b.position);
  return out;
}

std::vector<double> forces(const railway::PushResult& r) {
  std::vector<double> out;
  for (const auto& s : r.curve) out.push_back(s.force), out.push_back(s.heave);
  return out;
}

// One packing shared by the tests that only read it (preparation is the expensive part).
const railway::Packing& shared_packing() {
  static const railway::Packing p = pack_with(1);
  return p;
}

// Statics of a prepared bed: the sleeper's faces carry its weight, the base most of it. Averaged
// over the first 0.5 mm of a push the faces carry W + m (v_end - v_start) / T (Newton; v the
// sleeper's vertical velocity from its heave at the first two and the last two samples): the tiny
// bed's short settling leaves the sleeper sinking at up to about 1 cm/s, 8 % of W in m dv / T on
// the consolidated bed (stop 30). The balance is checked to 3 % of W, which still tells a bed
// that carries the weight from one that carries ten times it or lets it hang.
void check_rests_on_its_base(const railway::Packing& packing) {
  railway::PushRun run;
  run.velocity = packing.config.push.velocity;
  run.distance = 5e-4;
  run.quiet = true;
  const railway::PushResult r = railway::run_push(packing, packing.config, run);
  railway::ResistanceParts mean;
  for (const auto& s : r.curve) {
    mean.base += s.support.base / r.curve.size();
    mean.crib += s.support.crib / r.curve.size();
    mean.shoulder += s.support.shoulder / r.curve.size();
    mean.top += s.support.top / r.curve.size();
  }
  const auto& c = r.curve;
  REQUIRE(c.size() >= 4);
  const std::size_t n = c.size();
  const double v_start = (c[1].heave - c[0].heave) / (c[1].time - c[0].time);
  const double v_end = (c[n - 1].heave - c[n - 2].heave) / (c[n - 1].time - c[n - 2].time);
  const double inertia = packing.sleeper.mass * (v_end - v_start) / c[n - 1].time;
  CAPTURE(r.curve.size(), mean.base, mean.crib, mean.shoulder, mean.top, r.sleeper_weight, inertia);
  CHECK(std::abs(mean.base + mean.crib + mean.shoulder + mean.top - r.sleeper_weight - inertia) <
        0.03 * r.sleeper_weight);
  CHECK(mean.base > 0.5 * r.sleeper_weight);
}

}  // namespace

TEST_CASE("the same seed gives bitwise the same packing and push on 1 and 2 threads", "[railway][threads]") {
  const railway::Packing& one = shared_packing();
  const railway::Packing two = pack_with(2);
  REQUIRE(one.bodies.size() > 4 * dem::kChunkSize);  // the threads' blocks span chunks
  REQUIRE(same_bits(positions(one), positions(two)));
  REQUIRE(one.sleeper.centre == two.sleeper.centre);
  const auto push_one = push_with(one, 1);
  const auto push_two = push_with(two, 2);
  REQUIRE(push_one.status == "finished");
  REQUIRE(same_bits(forces(push_one), forces(push_two)));
  REQUIRE(same_bits(push_one.end_position, push_two.end_position));
}

TEST_CASE("a saved and reloaded packing is the same packing and pushes bitwise the same", "[railway][io]") {
  const railway::Packing& original = shared_packing();
  const test::TempDir dir;
  const auto file = dir.path() / "packing.h5";
  railway::save_packing(file, original);
  const railway::Packing loaded = railway::load_packing(file);
  REQUIRE(loaded.bodies.size() == original.bodies.size());
  REQUIRE(same_bits(positions(loaded), positions(original)));
  for (std::size_t b = 0; b < loaded.bodies.size(); ++b) {
    REQUIRE(loaded.bodies[b].mass == original.bodies[b].mass);
    REQUIRE(loaded.bodies[b].velocity == original.bodies[b].velocity);
    REQUIRE(loaded.bodies[b].orientation.coeffs() == original.bodies[b].orientation.coeffs());
    REQUIRE(loaded.stones[b].id == original.stones[b].id);
    REQUIRE(loaded.stones[b].size == original.stones[b].size);
  }
  REQUIRE(loaded.sleeper.centre == original.sleeper.centre);
  REQUIRE(loaded.sleeper.mass == original.sleeper.mass);
  REQUIRE(loaded.sleeper.half_extent == original.sleeper.half_extent);
  REQUIRE(loaded.sleeper.material == original.sleeper.material);
  REQUIRE(loaded.domain.min == original.domain.min);
  REQUIRE(loaded.domain.max == original.domain.max);
  REQUIRE(loaded.domain.periodic == original.domain.periodic);
  REQUIRE(loaded.config.text == original.config.text);
  REQUIRE(loaded.config.seed == original.config.seed);
  // The springs of the settled bed's contacts come back exactly (stone-stone, floor, sleeper).
  REQUIRE(original.springs.size() > original.bodies.size());
  REQUIRE(loaded.springs.size() == original.springs.size());
  int kinds[3] = {0, 0, 0};
  for (std::size_t k = 0; k < loaded.springs.size(); ++k) {
    const auto& a = loaded.springs[k];
    const auto& b = original.springs[k];
    REQUIRE(a.kind == b.kind);
    REQUIRE(a.first == b.first);
    REQUIRE(a.second == b.second);
    REQUIRE(a.history.shear_force == b.history.shear_force);
    REQUIRE(a.history.rolling_moment == b.history.rolling_moment);
    REQUIRE(a.history.damping_force == b.history.damping_force);
    ++kinds[static_cast<int>(a.kind)];
  }
  CHECK(kinds[0] > 0);
  CHECK(kinds[1] > 0);
  CHECK(kinds[2] > 0);
  REQUIRE(same_bits(forces(push_with(loaded, 1)), forces(push_with(original, 1))));
}

TEST_CASE("on a tiny bed F(u) starts at zero and rises", "[railway][push]") {
  const railway::Packing& p = shared_packing();
  const railway::PushResult r = push_with(p, 1);
  REQUIRE(r.status == "finished");
  REQUIRE(r.curve.size() > 40);
  REQUIRE(r.curve.front().u == 0.0);
  INFO("F(0) = " << r.curve.front().force << " N, peak " << r.peak_force << " N at u = " << r.u_at_peak << " m");
  // Free across the track while it settled, the sleeper carries no lateral load at rest: |F(0)|
  // is the residue of the settling. The tiny bed settles for 0.1 s only and its sleeper still
  // moves then (see check_rests_on_its_base), so the residue is a few per cent of the peak, not
  // zero: 7.6 % at commit 1b7dfd5, below 5 % before its step change made another bed. A sleeper
  // held while settling would lock in the bed's lateral pressure: tens of per cent.
  CHECK(std::abs(r.curve.front().force) < 0.1 * r.peak_force);
  // It rises: the peak is ten times |F(0)| and not the first sample. (Where the peak falls, and
  // how far F softens after it, depends on the realisation: this small bed of balls can peak at
  // the end of its elastic rise and soften to a fifth of it by the end of the 1 mm push.)
  CHECK(r.peak_force > 10.0 * std::abs(r.curve.front().force));
  CHECK(r.peak_sample > 0);
  // Base, crib, shoulder and top carry all of F (each contact counts to one face), to
  // round-off; the base, dragged over the bed under the sleeper's weight, resists.
  for (const auto& s : r.curve) {
    const auto& q = s.parts;
    CHECK(std::abs(q.base + q.crib + q.shoulder + q.top - s.force) < 1e-9 * (std::abs(s.force) + 1.0));
  }
  const auto& at_peak = r.at_peak().parts;
  INFO("parts at the peak: base " << at_peak.base << ", crib " << at_peak.crib << ", shoulder " << at_peak.shoulder);
  CHECK(at_peak.base > 0.0);
  // The faces carry the sleeper's weight: at u = 0 the sleeper rests on the settled bed, so the
  // upward forces on its faces balance m g to the settling residue (force ratio 1e-3; 2 % allowed).
  // During the push it rises as the bed dilates, so the interval means need not sum to m g.
  const auto& q0 = r.curve.front().support;
  INFO("support at u = 0: base " << q0.base << ", crib " << q0.crib << ", shoulder " << q0.shoulder << " N; weight "
                                 << r.sleeper_weight << " N");
  CHECK(std::abs(q0.base + q0.crib + q0.shoulder + q0.top - r.sleeper_weight) < 0.02 * r.sleeper_weight);
  CHECK(r.curve.front().support.base > 0.5 * r.sleeper_weight);
  // The faces are pressed, never pulled (contact forces are never tensile).
  for (const auto& s : r.curve) {
    CAPTURE(s.u, s.pressing.base, s.pressing.crib, s.pressing.shoulder);
    CHECK(s.pressing.base >= 0.0);
    CHECK(s.pressing.crib >= 0.0);
    CHECK(s.pressing.shoulder >= 0.0);
  }
  CHECK(r.sleeper_friction == Approx(0.5));  // Table 1, stone-sleeper
  // At rest the base's normal force is the weight it carries.
  CHECK(r.curve.front().pressing.base == Approx(r.curve.front().support.base).epsilon(1e-12));
  // Contact forces: the 99.9 % quantile lies between the mean and the maximum.
  CHECK(r.mean_contact_force < r.contact_force_q999);
  CHECK(r.contact_force_q999 <= r.max_contact_force);
  // The drive (a speed-up over 0.1 mm, then the set velocity) ends within one step's travel of
  // u_end, and the sleeper is where the drive put it.
  CHECK(std::abs(r.curve.back().u - r.distance) <= r.velocity * r.time_step);
  // The mean force (work / u_end) lies between F(0) and the peak.
  CHECK(r.mean_force > r.curve.front().force);
  CHECK(r.mean_force < r.peak_force);
}

TEST_CASE("the mean force over a push is the work done per unit displacement", "[railway][push]") {
  // Reference: W = integral of F du. Each sample is F's mean over the interval ending at its u,
  // so sum F_k (u_k - u_(k-1)) is W exactly. F = k u sampled as interval means on uneven
  // intervals (a speed-up, then even steps): W = k u_end^2 / 2, the mean k u_end / 2.
  const double k = 2.0e6, u_end = 5e-3;
  std::vector<double> interval_ends = {1e-6, 4e-6, 1e-5, 3e-5};
  for (int i = 4; i <= 500; ++i) interval_ends.push_back(i * 1e-5);
  std::vector<railway::ForceSample> curve;
  double u_before = 0.0;
  for (double u : interval_ends) {
    railway::ForceSample sample;
    sample.u = u;
    sample.force = k * 0.5 * (u + u_before);
    curve.push_back(sample);
    u_before = u;
  }
  CHECK(railway::mean_over_displacement(curve) == Approx(k * curve.back().u / 2).epsilon(1e-12));
  // A single slip at the end moves the peak of a rising curve by its depth and the mean by its
  // share of the distance: a 10 % jump on the last 1 % of u moves the mean by about 0.2 %.
  auto slipped = curve;
  for (auto& s : slipped)
    if (s.u > 0.99 * u_end) s.force *= 1.1;
  const double moved = railway::mean_over_displacement(slipped) / railway::mean_over_displacement(curve) - 1.0;
  CHECK(moved == Approx(0.002).margin(0.0005));
  CHECK(railway::mean_over_displacement({}) == 0.0);
}

TEST_CASE("window means of F are the work done in each window of u per unit displacement", "[railway][push]") {
  // Reference: F = k u sampled as interval means on intervals that do not straddle the windows
  // gives each window's mean k times its middle, exactly.
  const double k = 2.0e6, width = 1e-3;
  const auto sampled = [k](const std::vector<double>& interval_ends) {
    std::vector<railway::ForceSample> curve;
    double u_before = 0.0;
    for (double u : interval_ends) {
      railway::ForceSample sample;
      sample.u = u;
      sample.force = k * 0.5 * (u + u_before);
      curve.push_back(sample);
      u_before = u;
    }
    return curve;
  };
  std::vector<double> even;
  for (int i = 1; i <= 500; ++i) even.push_back(i * 1e-5);
  const auto means = railway::window_mean_forces(sampled(even), width);
  REQUIRE(means.size() == 5);
  for (std::size_t w = 0; w < means.size(); ++w) CHECK(means[w] == Approx(k * (w + 0.5) * width).epsilon(1e-9));
  // Intervals of 0.7 mm straddle the edges: each window takes its overlap of every interval, so
  // the windows' work adds up to the whole push's (mean_over_displacement x u_end).
  std::vector<double> uneven;
  for (int i = 1; i <= 7; ++i) uneven.push_back(i * 0.7e-3);  // u_end 4.9 mm: 5 windows, the last 0.9 mm
  const auto curve = sampled(uneven);
  const auto straddled = railway::window_mean_forces(curve, width);
  REQUIRE(straddled.size() == 5);
  const double work = straddled[0] * 1e-3 + straddled[1] * 1e-3 + straddled[2] * 1e-3 + straddled[3] * 1e-3 +
                      straddled[4] * 0.9e-3;
  CHECK(work == Approx(railway::mean_over_displacement(curve) * 4.9e-3).epsilon(1e-12));
  // The first window holds the first interval (0.35 mm x k) for 0.7 mm and the second (1.05 mm x k) for 0.3 mm.
  CHECK(straddled[0] == Approx(k * (0.7 * 0.35e-3 + 0.3 * 1.05e-3)).epsilon(1e-12));
  // A tail shorter than 0.4 of a window is left out; none for an empty curve or no width.
  uneven.back() = 4.3e-3;
  CHECK(railway::window_mean_forces(sampled(uneven), width).size() == 4);
  CHECK(railway::window_mean_forces({}, width).empty());
  CHECK(railway::window_mean_forces(curve, 0.0).empty());
}

TEST_CASE("a sleeper held vertically keeps its height while the free one settles or rises", "[railway][push]") {
  const railway::Packing& p = shared_packing();
  railway::PushStudyConfig held = p.config;
  held.push.sleeper_held_vertically = true;
  railway::PushRun run;
  run.velocity = p.config.push.velocity;
  run.distance = p.config.push.distance;
  run.quiet = true;
  const railway::PushResult h = railway::run_push(p, held, run);
  const railway::PushResult f = push_with(p, 1);
  REQUIRE(h.status == "finished");
  CHECK(h.sleeper_held_vertically);
  CHECK_FALSE(f.sleeper_held_vertically);
  // Held: its vertical velocity is driven at zero, so the height never changes, to the bit.
  for (const auto& s : h.curve) CHECK(s.heave == 0.0);
  // Free: it moves vertically by more than round-off (the bed under it shears); the same start
  // state, so both begin with the weight on the faces (2 %, the settling residue).
  CAPTURE(f.final_heave);
  CHECK(std::abs(f.final_heave) > 1e-6);
  const auto& q0 = h.curve.front().support;
  CHECK(std::abs(q0.base + q0.crib + q0.shoulder + q0.top - h.sleeper_weight) < 0.02 * h.sleeper_weight);
  CHECK(h.curve.front().force == f.curve.front().force);
}

TEST_CASE("the pressing split takes each face's inward normal force", "[railway][push]") {
  // Reference: the sign convention of dem::BoxFace. A stone on a minus face pushes the box
  // towards +axis, one on a plus face towards -axis; both press. Tangential components (friction)
  // do not count.
  std::array<dem::Vec3, dem::kBoxFaces> faces;
  faces.fill(dem::Vec3::Zero());
  faces[dem::kMinusZ] = dem::Vec3(-3.0, 1.0, 40.0);  // the bed under the base: 40 N up
  faces[dem::kPlusZ] = dem::Vec3(0.0, 0.0, -2.0);    // a stone on top: 2 N down
  faces[dem::kMinusY] = dem::Vec3(-1.0, 5.0, 0.5);   // crib sides: 5 N and 7 N inwards
  faces[dem::kPlusY] = dem::Vec3(-2.0, -7.0, 0.5);
  faces[dem::kMinusX] = dem::Vec3(1.0, 0.0, 0.0);    // trailing end 1 N, leading end 11 N
  faces[dem::kPlusX] = dem::Vec3(-11.0, 0.2, 0.0);
  const railway::ResistanceParts p = railway::pressing_parts(faces);
  CHECK(p.base == 40.0);
  CHECK(p.top == 2.0);
  CHECK(p.crib == 12.0);
  CHECK(p.shoulder == 12.0);
  // The lateral part of the ends is the leading end's push minus the trailing end's.
  CHECK(railway::resistance_parts(faces).shoulder == 10.0);
}

namespace {

// Prepares the tiny bed with `config`, which adds one stage between deposition and settling,
// and checks that stage ran under `name` for its set `duration` (s). `stage_base`, when given,
// receives the height of the sleeper's base at the end of that stage.
railway::Packing prepared_with_stage(const railway::PushStudyConfig& config, const char* name, double duration,
                                     double* stage_base = nullptr) {
  railway::PreparationReport report;
  railway::Packing packing = railway::prepare_bed(config, true, report);
  REQUIRE(report.stages.size() == 3);
  CHECK(report.stages[1].name == name);
  CHECK(report.stages[1].simulated_time == Approx(duration).epsilon(1e-3));
  CHECK_FALSE(report.stages[0].sleeper_base);  // deposited before the sleeper is in
  REQUIRE(report.stages[1].sleeper_base);
  if (stage_base) *stage_base = *report.stages[1].sleeper_base;
  return packing;
}

}  // namespace

TEST_CASE("tamping packs the stones beside the sleeper and leaves it on its base", "[railway][tamping]") {
  // References: geometry and statics. The cut is tamping_depth shorter and narrower, so stones
  // that reached only into that shell stay (more stones kept); the sleeper ends at its design
  // size to round-off (1e-12 m); and, free vertically while tamped, it rests on the stones under
  // it: over the first 0.5 mm of a push its faces carry its weight (5 %), the base most of it.
  railway::PushStudyConfig config = tiny_config();
  const railway::Packing& plain = shared_packing();
  config.preparation.tamping_depth = 0.004;
  config.preparation.tamping_time = 0.02;
  double tamped_base = 0.0;
  const railway::Packing tamped = prepared_with_stage(config, "tamp", 0.02, &tamped_base);
  // Free, the stones it packs press it up out of its cut (4 mm of tamping: 2.0 mm up); held
  // tamping (the next test) exists for that.
  CHECK(tamped_base > config.geometry.sleeper_base() + 1e-4);
  CAPTURE(plain.bodies.size(), tamped.bodies.size(), tamped_base);
  CHECK(tamped.bodies.size() > plain.bodies.size());
  CHECK((tamped.sleeper.half_extent - plain.sleeper.half_extent).norm() < 1e-12);
  CHECK(tamped.sleeper.growth_rate.norm() == 0.0);
  check_rests_on_its_base(tamped);
}

TEST_CASE("held tamping keeps the sleeper at its design height", "[railway][tamping]") {
  // Reference: kinematics. Held vertically (tamping_sleeper_vertical = "held") the growing
  // sleeper's base stays at its design height to round-off (1e-12 m), however hard the stones
  // it packs press on it.
  railway::PushStudyConfig config = tiny_config();
  config.preparation.tamping_depth = 0.004;
  config.preparation.tamping_time = 0.02;
  config.preparation.tamping_sleeper_held = true;
  double held_base = 0.0;
  const railway::Packing tamped = prepared_with_stage(config, "tamp", 0.02, &held_base);
  CHECK(held_base == Approx(config.geometry.sleeper_base()).margin(1e-12));
  CHECK(tamped.bodies.size() > shared_packing().bodies.size());  // the cut kept more stones
}

TEST_CASE("radius expansion grows the stones back to their drawn size", "[railway][expansion]") {
  // References: geometry. Stones deposited 1 / 1.02 of their size and grown back in 4 factors
  // of 1.02^(1/4) end at the size they were drawn with: every kept stone's mass, pebble radii and
  // offsets equal the factory's draw of the same id to 1e-12 relative (round-off of five
  // products), and the stage lasts its set time.
  railway::PushStudyConfig config = tiny_config();
  config.preparation.expansion_strain = 0.02;
  config.preparation.expansion_steps = 4;
  config.preparation.expansion_time = 0.02;
  const railway::Packing expanded = prepared_with_stage(config, "expand", 0.02);
  const railway::StoneFactory factory(config);
  REQUIRE(expanded.stones.size() > 100);
  for (std::size_t k = 0; k < expanded.stones.size(); ++k) {
    const dem::ClumpSpec& grown = expanded.bodies[k];
    const dem::ClumpSpec drawn = factory.draw(expanded.stones[k].id).body;
    CHECK(grown.mass == Approx(drawn.mass).epsilon(1e-12));
    REQUIRE(grown.pebbles.size() == drawn.pebbles.size());
    for (std::size_t q = 0; q < grown.pebbles.size(); ++q) {
      CHECK(grown.pebbles[q].radius == Approx(drawn.pebbles[q].radius).epsilon(1e-12));
      CHECK((grown.pebbles[q].offset - drawn.pebbles[q].offset).norm() <= 1e-12 * drawn.pebbles[q].radius);
    }
  }
}

TEST_CASE("consolidation runs the bed at raised gravity, then settles it at 1 g", "[railway][consolidation]") {
  // References: the stage's set duration, and statics after it: back at 1 g the sleeper's faces
  // carry its weight (not ten times it) to 5 % (check_rests_on_its_base), the base most of it.
  railway::PushStudyConfig config = tiny_config();
  config.preparation.consolidation_gravity = 10.0;
  config.preparation.consolidation_time = 0.02;
  const railway::Packing consolidated = prepared_with_stage(config, "consolidate", 0.02);
  check_rests_on_its_base(consolidated);
}

TEST_CASE("a [[pair]] override sets the stone-sleeper friction the push runs with", "[railway][config]") {
  // Reference: the config itself. The push reports the stone-sleeper friction of its material
  // table: the override's 0.8 instead of Table 1's 0.5; pairs of a material with itself and
  // unknown names are refused naming file, key and value.
  const std::string pair = "\n[[pair]]\nmaterials = [\"ballast\", \"sleeper\"]\nfriction = 0.8\n";
  const railway::PushStudyConfig rough = railway::parse_push_config(mfdem::test::kTinyBed + pair, "tiny.toml");
  REQUIRE(rough.pairs.size() == 1);
  railway::PushRun run;
  run.velocity = rough.push.velocity;
  run.distance = 2e-4;
  run.quiet = true;
  CHECK(railway::run_push(shared_packing(), rough, run).sleeper_friction == 0.8);
  CHECK(railway::run_push(shared_packing(), tiny_config(), run).sleeper_friction == 0.5);
  const auto with_pair = [](const std::string& materials) {
    return railway::parse_push_config(std::string(mfdem::test::kTinyBed) + "\n[[pair]]\nmaterials = " + materials + "\nfriction = 0.8\n",
                                      "tiny.toml");
  };
  CHECK_THROWS_WITH(with_pair("[\"ballast\", \"ballast\"]"),
                    Catch::Contains("tiny.toml") && Catch::Contains("materials") && Catch::Contains("two different"));
  CHECK_THROWS_WITH(with_pair("[\"ballast\", \"rail\"]"),
                    Catch::Contains("rail") && Catch::Contains("ballast, sleeper, floor"));
}
