#include "studies/campaigns/run_slice.hpp"

#include <fmt/format.h>

#include "studies/config/config_error.hpp"

namespace mfdem::campaigns {

RunSlice parse_run_slice(const std::string& text, const std::string& option) {
  const auto refuse = [&] {
    throw config::ConfigError(fmt::format("{} {}: expected K/N with 0 <= K < N (this process's share of N, counted "
                                          "from 0, e.g. 0/4 ... 3/4)", option, text));
  };
  const auto slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size() || text.size() > 20) refuse();
  const std::string k = text.substr(0, slash), n = text.substr(slash + 1);
  if (k.find_first_not_of("0123456789") != std::string::npos || n.find_first_not_of("0123456789") != std::string::npos)
    refuse();
  RunSlice slice{std::stoull(k), std::stoull(n)};
  if (slice.count == 0 || slice.index >= slice.count) refuse();
  return slice;
}

}  // namespace mfdem::campaigns
