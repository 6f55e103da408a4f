// The progress mirror (studies/scene/progress.hpp): a quiet run's stage line reaches a file that
// the study's reporting process reads, at most every 2 s, and is gone when the run ends.
#include <catch2/catch.hpp>

#include <filesystem>

#include "studies/scene/progress.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::scene::Progress;
using mfdem::scene::ProgressMirror;
using mfdem::scene::read_progress_mirror;

TEST_CASE("a quiet stage made while a mirror lives writes its line to the mirror's file", "[scene][progress]") {
  const mfdem::test::TempDir dir;
  const auto file = dir.path() / "progress.txt";
  Progress before("compare", 4.0, true);  // a study's own line, made before its runs
  {
    const ProgressMirror mirror(file);
    before.update(1.0);
    CHECK(read_progress_mirror(file).empty());  // not the run's: not mirrored

    Progress settle("settle    ", 0.5, true);  // padded as the stage runner pads its labels
    settle.update(0.17);
    CHECK(read_progress_mirror(file) == "settle 34 %");
    settle.update(0.25);  // within 2 s of the last line: not rewritten
    CHECK(read_progress_mirror(file) == "settle 34 %");

    Progress push("push", 5.0, true);  // the next stage's first line is written at once
    push.update(6.0);                  // past the end: 100 %, never more
    CHECK(read_progress_mirror(file) == "push 100 %");
  }
  CHECK_FALSE(std::filesystem::exists(file));  // the run is over: no stale line
  CHECK(read_progress_mirror(file).empty());
}

TEST_CASE("a mirror made inside another gives the line back to the outer one when it ends", "[scene][progress]") {
  const mfdem::test::TempDir dir;
  const auto outer_file = dir.path() / "outer.txt", inner_file = dir.path() / "inner.txt";
  const ProgressMirror outer(outer_file);
  {
    const ProgressMirror inner(inner_file);
    Progress stage("tamp", 1.0, true);
    stage.update(0.5);
    CHECK(read_progress_mirror(inner_file) == "tamp 50 %");
    CHECK(read_progress_mirror(outer_file).empty());
  }
  CHECK_FALSE(std::filesystem::exists(inner_file));
  Progress push("push", 1.0, true);
  push.update(0.2);
  CHECK(read_progress_mirror(outer_file) == "push 20 %");
}
