#pragma once
// A study command refusing bad options before any run: each case exits 2 naming what it names, and
// no run store is made in `out`.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/run_mfdem.hpp"

namespace mfdem::test {

struct RefusalCase {
  std::vector<std::string> args;      // after `COMMAND CONFIG --out OUT`
  std::vector<std::string> expected;  // each in the error message
};

inline void check_refused_before_any_run(const std::string& command, const std::string& config,
                                         const std::filesystem::path& out, const std::vector<RefusalCase>& cases) {
  for (const auto& c : cases) {
    std::vector<std::string> args = {command, config, "--out", out.string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto result = run_mfdem(args);
    CAPTURE(c.args, result.err);
    CHECK(result.status == 2);
    for (const auto& e : c.expected) CHECK_THAT(result.err, Catch::Matchers::Contains(e));
    CHECK_FALSE(std::filesystem::exists(out / "runs"));  // nothing run, no store made
  }
}

}  // namespace mfdem::test
