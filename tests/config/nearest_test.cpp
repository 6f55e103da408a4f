// Spelling suggestions: the optimal-string-alignment distance and when a candidate is offered.
#include <catch2/catch.hpp>

#include "studies/config/nearest.hpp"

using mfdem::config::edit_distance;
using mfdem::config::nearest;

TEST_CASE("edit distance counts a swap of neighbouring letters as one edit", "[config]") {
  CHECK(edit_distance("materails", "materials") == 1);
  CHECK(edit_distance("friction", "friction") == 0);
  CHECK(edit_distance("Friction", "friction") == 0);  // case is ignored
  CHECK(edit_distance("kitten", "sitting") == 3);     // the textbook Levenshtein example
  CHECK(edit_distance("", "abc") == 3);
}

TEST_CASE("nearest offers only plausible typos", "[config]") {
  const std::vector<std::string> keys{"materials", "sleeper", "push"};
  CHECK(nearest("materails", keys) == "materials");
  CHECK(nearest("sleepr", keys) == "sleeper");
  CHECK_FALSE(nearest("gravity", keys).has_value());
  CHECK_FALSE(nearest("pu", keys).has_value());  // 2 edits of a 2-letter word is a guess, not a typo
  CHECK_FALSE(nearest("materials", {}).has_value());
}
