// The single-sleeper section's profile and the rejection of geometry that cannot be built.
#include <catch2/catch.hpp>

#include "studies/railway/section_geometry.hpp"

using mfdem::railway::SectionGeometry;

TEST_CASE("the ballast profile is flat to the shoulder crest and falls 1:1.5 to the toe",
          "[railway][geometry]") {
  // Reference: the design notes' section, 0.30 m under a 0.21 m sleeper, 0.45 m shoulder,
  // slope 1:1.5: crest at 1.3 + 0.45 = 1.75 m, toe 1.5 x 0.51 = 0.765 m further. Exact.
  const SectionGeometry g;
  CHECK(g.ballast_top() == Approx(0.51));
  CHECK(g.crest_half_width() == Approx(1.75));
  CHECK(g.toe_half_width() == Approx(1.75 + 0.765));
  CHECK(g.surface_height(0.0) == Approx(0.51));
  CHECK(g.surface_height(-1.75) == Approx(0.51));
  CHECK(g.surface_height(1.75 + 0.3) == Approx(0.51 - 0.2));
  CHECK(g.surface_height(3.0) == 0.0);
  CHECK(g.inside_sleeper(1.2, 0.3, 0.4));
  CHECK_FALSE(g.inside_sleeper(1.2, 0.3, 0.25));  // below the base: ballast under the sleeper
  CHECK_FALSE(g.inside_sleeper(1.2, 0.0, 0.4));   // crib between sleepers
}

TEST_CASE("bad section geometry is refused with the parameter, its value and the need",
          "[railway][geometry]") {
  const double stone = 0.063;
  SectionGeometry g;
  CHECK_NOTHROW(validate(g, stone));
  SECTION("a crib narrower than a stone") {
    g.sleeper_width = 0.56;  // 0.04 m between sleepers 0.6 m apart
    CHECK_THROWS_WITH(validate(g, stone), Catch::Contains("crib") && Catch::Contains("0.56"));
  }
  SECTION("negative depth") {
    g.depth_under_sleeper = -0.1;
    CHECK_THROWS_WITH(validate(g, stone), Catch::Contains("depth_under_sleeper = -0.1 m") &&
                                              Catch::Contains("must be > 0"));
  }
  SECTION("a shoulder narrower than a stone") {
    g.shoulder_width = 0.03;
    CHECK_THROWS_WITH(validate(g, stone), Catch::Contains("shoulder_width = 0.03 m") &&
                                              Catch::Contains("at least one stone (0.063 m)"));
  }
  SECTION("a sleeper outside the box") {
    g.sleeper_width = 0.8;
    CHECK_THROWS_WITH(validate(g, stone), Catch::Contains("sleeper_width = 0.8 m") &&
                                              Catch::Contains("fit in the section"));
  }
  SECTION("a periodic crib of one stone, too narrow to keep the sleeper clear of the periodic faces") {
    g.sleeper_width = 0.6 - 0.07;  // a 0.07 m crib: one stone (0.063 m), less than 1.2 stones
    CHECK_THROWS_WITH(validate(g, stone), Catch::Contains("with periodic ends the crib") &&
                                              Catch::Contains("at least 1.2 stones (0.0756 m)"));
    g.periodic_along_track = false;  // walls along the track: one stone is enough
    CHECK_NOTHROW(validate(g, stone));
  }
  SECTION("a periodic section shorter than three stones") {
    g.section_length = 0.15;
    g.sleeper_width = 0.1;
    CHECK_THROWS_WITH(validate(g, stone), Catch::Contains("section_length = 0.15 m"));
  }
}
