// The multi-layer model on a prepared bed: a policy's conversion and re-settling
// (studies/railway/model_bed.hpp). The bitwise claims are memcmp comparisons; the bed is the tiny
// push-test bed (tiny_bed.hpp) drawn as 6-pebble clumps instead of balls.
#include <catch2/catch.hpp>
#include <omp.h>

#include <cstring>
#include <string>

#include "fidelity/grading.hpp"
#include "fidelity/shape_library.hpp"
#include "studies/config/config_error.hpp"
#include "studies/railway/bed_preparation.hpp"
#include "studies/railway/model_bed.hpp"
#include "studies/railway/push_test.hpp"
#include "studies/railway/section_simulation.hpp"
#include "tests/railway/tiny_bed.hpp"

using namespace mfdem;

namespace {

std::string with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

std::string tiny_clump_text() {
  return with(test::kTinyBed, "representation = \"ball\"", "representation = \"clump\"");
}

railway::Packing prepare(const std::string& text) {
  railway::PreparationReport report;
  return railway::prepare_bed(railway::parse_push_config(text, "tiny.toml"), true, report);
}

const railway::Packing& clump_bed() {
  static const railway::Packing p = prepare(tiny_clump_text());
  return p;
}

railway::PushResult push(const railway::Packing& p, const railway::PushStudyConfig& c, int threads = 1) {
  const int previous = omp_get_max_threads();
  omp_set_num_threads(threads);
  railway::PushRun run;
  run.velocity = c.push.velocity;
  run.distance = c.push.distance;
  run.quiet = true;
  railway::PushResult r = railway::run_push(p, c, run);
  omp_set_num_threads(previous);
  return r;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

std::vector<double> curve_bits(const railway::PushResult& r) {
  std::vector<double> out;
  for (const auto& s : r.curve) out.push_back(s.force), out.push_back(s.heave);
  return out;
}

std::vector<dem::Vec3> positions(const std::vector<dem::ClumpSpec>& bodies) {
  std::vector<dem::Vec3> out;
  for (const auto& b : bodies) out.push_back(b.position);
  return out;
}

railway::ModelBed model(const railway::Packing& p, const railway::PushStudyConfig& c, const std::string& policy,
                        bool resettle = true) {
  railway::ModelControl control;
  control.quiet = true;
  control.resettle = resettle;
  return railway::model_bed(p, c, railway::make_policy(policy, p), control);
}

}  // namespace

TEST_CASE("all-clump leaves the packing bitwise unchanged and pushes as the plain push", "[railway][model]") {
  const railway::Packing& bed = clump_bed();
  const railway::ModelBed m = model(bed, bed.config, "all-clump");
  CHECK(m.report.converted == 0);
  CHECK(m.report.balls == 0);
  CHECK(m.report.clumps == static_cast<std::int64_t>(bed.bodies.size()));
  CHECK(m.report.elements == bed.element_count());
  CHECK(m.report.element_ratio() == 1.0);
  CHECK_FALSE(m.report.resettling);
  CHECK(same_bits(positions(m.packing.bodies), positions(bed.bodies)));
  CHECK(m.packing.springs.size() == bed.springs.size());
  CHECK(same_bits(curve_bits(push(m.packing, bed.config)), curve_bits(push(bed, bed.config))));
}

TEST_CASE("layer-by-height converts exactly the stones whose centre lies below h", "[railway][model]") {
  const railway::Packing& bed = clump_bed();
  const double base = railway::bed_frame(bed).scale().sleeper_base;
  for (const double fraction : {0.0, 0.5, 1.0}) {
    const std::string policy = "layer-by-height:h_fraction=" + std::to_string(fraction);
    const railway::ModelBed m = model(bed, bed.config, policy, false);
    std::int64_t below = 0;
    for (std::size_t k = 0; k < bed.bodies.size(); ++k) {
      const bool is_below = bed.bodies[k].position.z() < fraction * base;
      below += is_below;
      CHECK((m.packing.bodies[k].material == railway::kBall) == is_below);
      CHECK(m.packing.bodies[k].pebbles.size() == (is_below ? 1u : bed.bodies[k].pebbles.size()));
    }
    CAPTURE(fraction, below);
    CHECK(m.report.balls == below);
    CHECK(m.report.clumps + m.report.balls == static_cast<std::int64_t>(bed.bodies.size()));
    if (fraction == 0.0) CHECK(below == 0);
    if (fraction == 1.0) CHECK(below > 100);  // the bed under the sleeper
    // Every ball has its clump's mass and centre: the total mass is kept to the last bit of
    // the summation (the same masses in the same order).
    double before = 0.0, after = 0.0;
    for (std::size_t k = 0; k < bed.bodies.size(); ++k) before += bed.bodies[k].mass, after += m.packing.bodies[k].mass;
    CHECK(after == before);
    CHECK(same_bits(positions(m.packing.bodies), positions(bed.bodies)));
  }
}

TEST_CASE("one-pebble clumps made balls by all-ball with mu_r = 0 push bitwise as the same bed of balls",
          "[railway][model]") {
  // The tiny bed of balls, and the same bodies marked as one-pebble clumps of the ballast.
  std::string text = with(test::kTinyBed, "rolling_friction = 0.3", "rolling_friction = 0.0");
  text += "[fidelity]\nrolling_friction = 0.0\n";
  const railway::Packing balls = prepare(text);
  railway::Packing clumps = balls;
  for (auto& b : clumps.bodies) {
    REQUIRE(b.material == railway::kBall);
    b.material = railway::kBallast;
  }
  const railway::ModelBed m = model(clumps, balls.config, "all-ball", false);
  CHECK(m.report.converted == static_cast<std::int64_t>(balls.bodies.size()));
  CHECK(m.report.springs_dropped == 0);
  CHECK(same_bits(curve_bits(push(m.packing, balls.config)), curve_bits(push(balls, balls.config))));
}

TEST_CASE("a converted and re-settled bed pushes bitwise the same on 1 and 2 threads", "[railway][model][threads]") {
  const railway::Packing& bed = clump_bed();
  const auto run = [&](int threads) {
    const int previous = omp_get_max_threads();
    omp_set_num_threads(threads);
    const railway::ModelBed m = model(bed, bed.config, "layer-by-height:h_fraction=0.5");
    omp_set_num_threads(previous);
    return std::make_pair(m, push(m.packing, bed.config, threads));
  };
  const auto [one, push_one] = run(1);
  const auto [two, push_two] = run(2);
  REQUIRE(one.report.resettling);
  CHECK(one.report.converted > 0);
  CHECK(one.report.conversion_point == "after preparation, re-settled");
  CHECK(one.report.resettling->steps == two.report.resettling->steps);
  CHECK(same_bits(positions(one.packing.bodies), positions(two.packing.bodies)));
  CHECK(same_bits(curve_bits(push_one), curve_bits(push_two)));
  CHECK(push_one.peak_force > 0.0);
}

TEST_CASE("a bad [fidelity] table is refused naming file, key and value", "[railway][model][config]") {
  const auto refused = [](const std::string& table) {
    try {
      railway::parse_push_config(tiny_clump_text() + "[fidelity]\n" + table + "\n", "tiny.toml");
    } catch (const config::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK_THAT(refused("policy = \"layer-by-hight:h=0.05\""),
             Catch::Contains("tiny.toml") && Catch::Contains("fidelity.policy") &&
                 Catch::Contains("unknown fidelity policy 'layer-by-hight'"));
  CHECK_THAT(refused("policy = \"layer-by-height:h=0.5\""),
             Catch::Contains("fidelity.policy") && Catch::Contains("h = 0.5") && Catch::Contains("0.08 (the sleeper base)"));
  CHECK_THAT(refused("policy = \"zone-by-distance:d=-0.01\""), Catch::Contains("d = -0.01"));
  CHECK_THAT(refused("policy = \"zone-by-distance\""), Catch::Contains("needs d"));
  CHECK_THAT(refused("rolling_friction = -0.1"), Catch::Contains("fidelity.rolling_friction = -0.1"));
  CHECK_THAT(refused("ball_friction = -1"), Catch::Contains("fidelity.ball_friction = -1"));
  CHECK_THAT(refused("polcy = \"all-ball\""), Catch::Contains("polcy") && Catch::Contains("policy"));
  CHECK(refused("policy = \"layer-by-height:h=0.04\"\nrolling_friction = 0.2") == "accepted");
}

TEST_CASE("a model whose balls are too wide for the periodic section is refused naming the key", "[railway][model][config]") {
  railway::PushStudyConfig c = railway::parse_push_config(tiny_clump_text(), "tiny.toml");  // 0.2 m section
  c.geometry.sleeper_width = 0.05;  // a 0.15 m crib: the section length decides
  fidelity::ConvertedBed bed;
  dem::ClumpSpec ball;
  ball.pebbles = {{dem::Vec3::Zero(), 0.045}};
  bed.bodies = {ball};
  // 2 x (0.09 + 0.2 x 0.045) = 0.198 m fits in 0.2 m; a 0.05 m ball needs 0.22 m.
  CHECK_NOTHROW(railway::check_balls_fit(c, bed));
  bed.bodies[0].pebbles[0].radius = 0.05;
  CHECK_THROWS_WITH(railway::check_balls_fit(c, bed), Catch::Contains("tiny.toml") &&
                                                          Catch::Contains("section.section_length = 0.2") &&
                                                          Catch::Contains("0.2200 m"));
  // The crib, 0.2 - 0.06 = 0.14 m with the tiny bed's own sleeper: a 0.15 m ball is wider.
  c.geometry.sleeper_width = 0.06;
  bed.bodies[0].pebbles[0].radius = 0.03;
  CHECK_NOTHROW(railway::check_balls_fit(c, bed));
  c.geometry.section_length = 0.5;
  c.geometry.sleeper_width = 0.4;  // a 0.1 m crib
  bed.bodies[0].pebbles[0].radius = 0.051;
  CHECK_THROWS_WITH(railway::check_balls_fit(c, bed), Catch::Contains("section.sleeper_width = 0.4") &&
                                                          Catch::Contains("crib of 0.1000 m") &&
                                                          Catch::Contains("0.1020 m"));
}

TEST_CASE("a bed converted after its deposition is prepared as the model's own and says so", "[railway][model]") {
  railway::PreparationControl control;
  control.quiet = true;
  const railway::PushStudyConfig c = railway::parse_push_config(tiny_clump_text(), "tiny.toml");
  control.convert_after_deposit =
      fidelity::PolicyRegistry::builtin().make("layer-by-height:h_fraction=0.5", {c.geometry.sleeper_base()});
  railway::PreparationReport report;
  const railway::Packing p = *railway::prepare_bed(c, control, report);
  CHECK(p.model == "layer-by-height:h=0.04,h_fraction=0.5");
  CHECK(p.conversion_point == "after deposition");
  std::int64_t balls = 0;
  for (const auto& b : p.bodies) balls += b.material == railway::kBall;
  CHECK(balls > 50);
  CHECK(balls < static_cast<std::int64_t>(p.bodies.size()));
  REQUIRE(report.stages.size() >= 3);
  CHECK(report.stages[1].name == "convert");
  // The model's push records it without converting again.
  const railway::ModelBed m = model(p, p.config, "all-clump");
  CHECK(m.report.converted == 0);
  CHECK(m.report.balls == balls);
  CHECK(m.report.policy == p.model);
  CHECK(m.report.conversion_point == "after deposition");
  CHECK(m.report.elements_before > m.report.elements);  // the same stones as clumps
}

TEST_CASE("the largest ball any policy can make fits study, standard and paper, and on mini the balls of the upper size D",
          "[railway][model][config]") {
  // The equal-volume ball of the largest template at a size, against the periodic section
  // (check_balls_fit) and the crib, the sleeper's gap to its periodic image. Standard and paper
  // take the grading's largest size (EN 13450's 80 mm sieve passes everything); mini's 0.08 m
  // crib takes every ball up to the upper size D = 63 mm (97 % passing) and beyond, to 77 mm.
  const auto& library = fidelity::standard_library();
  const auto ball_of_size = [&](double size) {
    double radius = 0.0;
    for (const auto& t : library.templates) radius = std::max(radius, t.equivalent_radius(size));
    fidelity::ConvertedBed bed;
    dem::ClumpSpec ball;
    ball.pebbles = {{dem::Vec3::Zero(), radius}};
    bed.bodies = {ball};
    return bed;
  };
  const double largest = fidelity::SieveCurve::en13450_31_5_63().largest_mm() * 1e-3;
  for (const char* preset : {"study", "standard", "paper"}) {
    CAPTURE(preset);
    CHECK_NOTHROW(railway::check_balls_fit(railway::load_push_config(preset), ball_of_size(largest)));
  }
  const railway::PushStudyConfig mini = railway::load_push_config("mini");
  CHECK_NOTHROW(railway::check_balls_fit(mini, ball_of_size(0.077)));
  CHECK_THROWS_WITH(railway::check_balls_fit(mini, ball_of_size(largest)), Catch::Contains("section.sleeper_width"));
}
