#pragma once
// The calibration loop's record: one CSV line per finished run, appended and flushed as each
// finishes, read back when a loop starts again (calibration_loop.hpp).
//
//   # mfdem calibration record 1
//   # options <fingerprint of what decides the runs>
//   run,level,seed,x1..xd,y1..ym
//   0,expensive,1,0.25,...
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "calibration/misfit_surrogate.hpp"

namespace mfdem::calibration {

struct RecordedRun {
  Evaluation run;
  std::uint64_t seed = 1;
};

class LoopRecord {
 public:
  // Opens `path` (creating it with the header when absent). Throws std::runtime_error naming the
  // file when it holds another loop's record (another fingerprint) or a malformed line other than
  // a last line cut short (dropped: the run it recorded is evaluated again).
  LoopRecord(std::filesystem::path path, std::string fingerprint, int parameters, int outputs);

  const std::vector<RecordedRun>& runs() const { return runs_; }
  void append(const RecordedRun& run);  // written and flushed at once

 private:
  std::filesystem::path path_;
  int parameters_, outputs_;
  std::vector<RecordedRun> runs_;
};

}  // namespace mfdem::calibration
