// The expected cost of a study's missing runs, from the walls of its finished runs.
#include <catch2/catch.hpp>

#include <filesystem>

#include "studies/campaigns/run_costs.hpp"
#include "studies/railway/push_config.hpp"
#include "tests/campaigns/micro_compare.hpp"
#include "tests/support/temp_dir.hpp"

namespace campaigns = mfdem::campaigns;
namespace fs = std::filesystem;
using mfdem::runs::RunRecord;

namespace {

// A finished (or failed) run of the given walls, written without a simulation.
void put(mfdem::runs::RunStore& store, const std::string& key, double preparation, double push, bool finished = true) {
  store.ensure(key, "rev", [&](const fs::path&) {
    RunRecord r;
    r.status = finished ? "finished" : "failed";
    if (!finished) r.message = "unstable";
    r.numbers = {{campaigns::number::kPreparationWall, preparation},
                 {campaigns::number::kPushWall, push},
                 {campaigns::number::kDepositionWall, 60.0}};
    return r;
  });
}

}  // namespace

TEST_CASE("a study's missing runs are weighed by their model's wall in the store", "[campaigns]") {
  const mfdem::test::TempDir dir;
  campaigns::CompareRequest request;
  request.config = mfdem::railway::parse_push_config(mfdem::test::micro_bed(), "micro.toml");
  request.models = campaigns::parse_models("all-clump,all-ball,layer-by-height:h=0.1", "--models");
  request.seeds = {1, 2, 3};
  const auto keys = campaigns::run_keys(request);  // seed by seed, models in order
  mfdem::runs::RunStore store(dir.path() / "store");

  SECTION("an empty store counts runs") {
    const auto costs = expected_run_costs(store, request);
    CHECK_FALSE(costs.measured);
    CHECK(costs.missing == 9.0);
  }
  SECTION("walls of finished runs, a failed run not counted, a deposition for an unstarted seed") {
    put(store, keys[0], 300, 100);         // seed 1, all-clump: 400 s
    put(store, keys[1], 100, 20);          // seed 1, all-ball: 120 s
    put(store, keys[2], 1, 1, false);      // seed 1, layer: failed (published, its wall not a model's cost)
    put(store, keys[3], 380, 120);         // seed 2, all-clump: 500 s
    const auto costs = expected_run_costs(store, request);
    REQUIRE(costs.measured);
    const double clump = 450, ball = 120, layer = (clump + ball) / 2, deposition_share = 60.0 / 3;
    CHECK(costs.seconds[4] == Approx(ball));                      // seed 2 has its deposition
    CHECK(costs.seconds[5] == Approx(layer));                     // a model with no finished run
    CHECK(costs.seconds[6] == Approx(clump + deposition_share));  // seed 3 has none yet
    CHECK(costs.missing == Approx(ball + layer + clump + ball + layer + 3 * deposition_share));
  }
}
