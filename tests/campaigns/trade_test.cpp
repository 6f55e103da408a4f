// `mfdem trade`'s plan and table (studies/campaigns/trade.hpp): the knobs set in a config as the
// config's own keys, the reference at every knob's accurate end, the settings past an edge refused
// before any run with the knob named, and the edges read from the runs.
#include <catch2/catch.hpp>

#include "studies/campaigns/trade.hpp"
#include "studies/config/config_error.hpp"
#include "tests/support/temp_dir.hpp"

using namespace mfdem;
using Catch::Matchers::Contains;

namespace {

const campaigns::KnobSpec& knob(const std::string& name) {
  for (const auto& k : campaigns::trade_knobs())
    if (name == k.name) return k;
  throw std::logic_error("no knob " + name);
}

campaigns::TradeRequest request(const std::vector<std::string>& knobs) {
  campaigns::TradeRequest r;
  r.config = railway::load_push_config("mini");
  r.seeds = {1, 2};
  for (const auto& k : knobs) r.knobs.push_back(campaigns::parse_knob(k, "--knob"));
  return r;
}

}  // namespace

TEST_CASE("trade knobs are parsed with their values, and a bad one is refused naming it", "[campaigns][trade]") {
  const auto k = campaigns::parse_knob("velocity=0.1,0.025,0.05", "--knob");
  CHECK(std::string(k.spec->name) == "velocity");
  CHECK(k.values == std::vector<double>{0.025, 0.05, 0.1});
  for (const auto& [text, words] : std::vector<std::pair<std::string, std::string>>{
           {"speed=1", "unknown knob 'speed'"}, {"velocity", "no '='"}, {"velocity=0.1,fast", "'fast' is not a number"},
           {"velocity=0.1,0.1", "given twice"}, {"velocity=inf", "not a finite number"}, {"velocity=", "no value"}})
    CHECK_THROWS_WITH(campaigns::parse_knob(text, "--knob"), Contains("--knob " + text) && Contains(words) &&
                                                                 Contains("time_step_safety, velocity"));
}

TEST_CASE("a knob sets the config's own key, and the run's key and deposition follow what it changes",
          "[campaigns][trade]") {
  const railway::PushStudyConfig mini = railway::load_push_config("mini");
  const campaigns::Model model;
  const auto fast = campaigns::with_knob(mini, knob("velocity"), 0.1);
  CHECK(fast.push.velocity == 0.1);
  CHECK(fast.push.distance == mini.push.distance);
  CHECK(campaigns::run_key(fast, model, 1) != campaigns::run_key(mini, model, 1));
  // A setting of the push alone shares the seed's deposition; the time step does not.
  CHECK(campaigns::deposition_key(fast, 1) == campaigns::deposition_key(mini, 1));
  CHECK(campaigns::with_knob(mini, knob("push_damping"), 0.3).push.local_damping == 0.3);
  // The config's own value leaves it as it is: a compare study's runs of it are found by their keys.
  CHECK(campaigns::with_knob(mini, knob("velocity"), mini.push.velocity).text == mini.text);
  CHECK(campaigns::with_knob(mini, knob("stiffness_scaling"), 1.0).text == mini.text);
  // What acts after the deposition (the settling's criterion here) shares it; the model's
  // prepared bed is its own.
  const auto creeping = campaigns::with_knob(mini, knob("creep_ratio"), 2e-4);
  REQUIRE(creeping.preparation.creep_ratio == 2e-4);
  CHECK(creeping.preparation.equilibrium_ratio == mini.preparation.equilibrium_ratio);
  CHECK(campaigns::deposition_key(creeping, 1) == campaigns::deposition_key(mini, 1));
  CHECK(campaigns::prepared_bed_key(creeping, model, 1) != campaigns::prepared_bed_key(mini, model, 1));
  CHECK(campaigns::run_key(creeping, model, 1) != campaigns::run_key(mini, model, 1));
  const auto coarse = campaigns::with_knob(mini, knob("time_step_safety"), 0.6);
  CHECK(coarse.time_step_safety == 0.6);
  CHECK(campaigns::deposition_key(coarse, 1) != campaigns::deposition_key(mini, 1));
  // Stiffness: the stones' kn and ks scaled, nothing else of the material.
  const auto soft = campaigns::with_knob(mini, knob("stiffness_scaling"), 0.1);
  CHECK(soft.ballast.normal_stiffness == Approx(0.1 * mini.ballast.normal_stiffness).epsilon(1e-15));
  CHECK(soft.ballast.shear_stiffness == Approx(0.1 * mini.ballast.shear_stiffness).epsilon(1e-15));
  CHECK(soft.ballast.density == mini.ballast.density);
  CHECK(soft.ballast.friction == mini.ballast.friction);
  CHECK(soft.ballast.damping_ratio == mini.ballast.damping_ratio);
  CHECK(soft.sleeper.normal_stiffness == mini.sleeper.normal_stiffness);
}

TEST_CASE("a trade plan runs the reference at every knob's accurate end and refuses the settings past an edge",
          "[campaigns][trade]") {
  const auto r = request({"time_step_safety=0.2,0.6,1.01", "stiffness_scaling=0,0.1,1", "velocity=0.025,0.1,50",
                          "push_damping=0,0.5,1"});
  const campaigns::TradePlan plan = campaigns::plan_trade(r);
  CHECK(plan.reference.time_step_safety == 0.2);            // the smallest step
  CHECK(plan.reference.ballast.normal_stiffness == r.config.ballast.normal_stiffness);  // full stiffness
  CHECK(plan.reference.push.velocity == 0.025);             // the slowest push
  CHECK(plan.reference.push.local_damping == 0.0);          // no damping
  REQUIRE(plan.settings.size() == 1 + 4 * 2);
  // From the accurate end outwards: stiffness 0.1 before 0; past each edge a refusal naming the knob.
  CHECK(plan.settings[3].label == "stiffness_scaling=0.1");
  CHECK(plan.settings[4].label == "stiffness_scaling=0");
  for (const char* label : {"time_step_safety=1.01", "stiffness_scaling=0", "velocity=50", "push_damping=1"}) {
    const auto s = std::find_if(plan.settings.begin(), plan.settings.end(), [&](const auto& x) { return x.label == label; });
    REQUIRE(s != plan.settings.end());
    CAPTURE(label, s->refused);
    CHECK_THAT(s->refused, Contains(std::string("--knob ") + label));
  }
  // The rest run: the reference and one value inside each knob's range.
  CHECK(plan.compare.models.size() == 5);
  CHECK(plan.compare.label_of(0).rfind("reference:", 0) == 0);
  CHECK(plan.compare.config_of(2).ballast.normal_stiffness == Approx(0.1 * r.config.ballast.normal_stiffness));
  // A reference the config refuses stops the study before any run.
  CHECK_THROWS_WITH(campaigns::plan_trade(request({"time_step_safety=1.5,2"})),
                    Contains("the reference setting") && Contains("time_step_safety=1.5"));
}

TEST_CASE("a trade table locates each knob's edge from its runs and says the margin the config keeps",
          "[campaigns][trade]") {
  const test::TempDir dir;
  runs::RunStore store(dir.path());
  const auto r = request({"time_step_safety=0.2,0.4,0.8,1.2"});
  const campaigns::TradePlan plan = campaigns::plan_trade(r);
  REQUIRE(plan.compare.models.size() == 3);  // 0.2 (reference), 0.4, 0.8; 1.2 refused
  // Stand-in runs: 0.8 blows up on seed 2 (a guard stopped it), the others finish.
  for (std::size_t m = 0; m < 3; ++m)
    for (std::uint64_t seed : r.seeds)
      store.ensure(campaigns::run_key(plan.compare.config_of(m), r.model, seed), "test", [&](const auto&) {
        if (m == 2 && seed == 2) throw std::runtime_error("the energy grew 3.1x in 200 steps");
        runs::RunRecord rec;
        rec.numbers = {{campaigns::number::kPeakForce, 50.0 + double(m)}, {campaigns::number::kMaxContactForce, 20.0},
                       {campaigns::number::kPreparationWall, 10.0 / double(m + 1)}, {campaigns::number::kPushWall, 1.0}};
        return rec;
      });
  const campaigns::TradeTable t = campaigns::trade_table(store, r, plan);
  REQUIRE(t.edges.size() == 1);
  const campaigns::KnobEdge& e = t.edges[0];
  CHECK(e.default_value == r.config.time_step_safety);
  REQUIRE(e.last_safe);
  CHECK(*e.last_safe == 0.4);
  REQUIRE(e.first_unsafe);
  CHECK(*e.first_unsafe == 0.8);
  CHECK_THAT(e.why, Contains("seed 2") && Contains("the energy grew"));
  REQUIRE(t.rows[1].measured);
  CHECK(t.rows[1].measured->peak_force.difference.mean == Approx(1.0 / 50.0).epsilon(1e-12));  // 51 N against 50 N
  CHECK(t.rows[1].measured->total_speedup == Approx(11.0 / 6.0).epsilon(1e-12));               // (10 + 1) / (5 + 1)
  CHECK_THAT(t.rows[3].status, Contains("refused: --knob time_step_safety=1.2"));
  std::ostringstream text;
  campaigns::print_trade_table(text, t);
  CHECK_THAT(text.str(), Contains("time_step_safety: safe at 0.4, unsafe at 0.8"));
}
