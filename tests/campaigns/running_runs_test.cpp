// What a study shows while its runs compute (campaigns::running_runs over RunStore::in_progress):
// each run in a work folder with the line its stages wrote, named by seed and model.
#include <catch2/catch.hpp>

#include "studies/campaigns/push_runs.hpp"
#include "studies/scene/progress.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::runs::RunRecord;
using mfdem::runs::RunStore;

TEST_CASE("running_runs names the runs being computed and their stages, and none once published",
          "[campaigns][runs][progress]") {
  const mfdem::test::TempDir dir;
  RunStore store(dir.path() / "store");
  CHECK(store.in_progress().empty());
  CHECK(mfdem::campaigns::running_runs(store).empty());

  std::string seen_inside, listed_key;
  store.ensure("s3-layer-by-height_h_fraction_0.5_mu_r_0.3-0123456789ab", "rev", [&](const std::filesystem::path& work) {
    const auto running = store.in_progress();
    REQUIRE(running.size() == 1);
    listed_key = running.front().key;
    CHECK(running.front().work == work);
    CHECK(mfdem::campaigns::running_runs(store).empty());  // started, nothing reported yet
    const mfdem::scene::ProgressMirror mirror(work / mfdem::campaigns::kRunProgressFile);
    mfdem::scene::Progress stage("settle    ", 1.0, true);
    stage.update(0.25);
    seen_inside = mfdem::campaigns::running_runs(store);
    return RunRecord{};
  });
  CHECK(listed_key == "s3-layer-by-height_h_fraction_0.5_mu_r_0.3-0123456789ab");
  CHECK(seen_inside == "s3-layer-by-height_h_fraction_0.5_mu_r_0.3 settle 25 %");
  CHECK(store.has("s3-layer-by-height_h_fraction_0.5_mu_r_0.3-0123456789ab"));
  CHECK(store.in_progress().empty());
  CHECK(mfdem::campaigns::running_runs(store).empty());
  CHECK_FALSE(std::filesystem::exists(dir.path() / "store" / "runs" /
                                      "s3-layer-by-height_h_fraction_0.5_mu_r_0.3-0123456789ab" /
                                      mfdem::campaigns::kRunProgressFile));
}
