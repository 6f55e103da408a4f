#pragma once
// The micro bed the campaign commands are tested end to end on (6-pebble clumps of 25 mm in a
// 0.12 m section, a 0.3 mm push: seconds a run), and the readers of what they write.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/railway/tiny_bed.hpp"

namespace mfdem::test {

inline std::string micro_bed() {
  std::string text = mfdem::test::kTinyBed;
  const auto swap = [&](const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
  swap("representation = \"ball\"", "representation = \"clump\"");
  swap("section_length = 0.20", "section_length = 0.12");
  swap("distance = 1e-3", "distance = 3e-4");
  return text;
}

inline std::string text_of(const std::filesystem::path& file) {
  std::stringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

// compare.csv without the wall-time columns (8-11: preparation, push, the two speedups; 36-37:
// element-steps per second and the relative cost per element-step), which differ from run to
// run; every other number (the per-seed differences of 38-41 too) is the simulation's and must
// repeat bitwise.
inline std::string without_wall_times(const std::string& csv) {
  std::stringstream in(csv), out;
  for (std::string line; std::getline(in, line);) {
    std::stringstream fields(line);
    int column = 0;
    for (std::string field; std::getline(fields, field, ',');) {
      if ((column < 8 || column > 11) && (column < 36 || column > 37)) out << field << ',';
      ++column;
    }
    out << '\n';
  }
  return out.str();
}

}  // namespace mfdem::test
