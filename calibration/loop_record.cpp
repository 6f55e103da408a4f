#include "calibration/loop_record.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mfdem::calibration {
namespace {

constexpr const char* kFormat = "# mfdem calibration record 1";

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream s(line);
  std::string field;
  while (std::getline(s, field, ',')) fields.push_back(field);
  return fields;
}

}  // namespace

LoopRecord::LoopRecord(std::filesystem::path path, std::string fingerprint, int parameters, int outputs)
    : path_(std::move(path)), parameters_(parameters), outputs_(outputs) {
  const std::string options = "# options " + fingerprint;
  if (!std::filesystem::exists(path_)) {
    std::ofstream out(path_);
    if (!out) throw std::runtime_error(fmt::format("{}: cannot create the calibration record", path_.string()));
    out << kFormat << "\n" << options << "\nrun,level,seed";
    for (int a = 0; a < parameters; ++a) out << ",x" << a + 1;
    for (int j = 0; j < outputs; ++j) out << ",y" << j + 1;
    out << "\n";
    return;
  }
  std::ifstream in(path_);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  const bool last_complete = !text.empty() && text.back() == '\n';
  if (lines.size() < 3 || lines[0] != kFormat)
    throw std::runtime_error(fmt::format("{}: not an mfdem calibration record", path_.string()));
  if (lines[1] != options)
    throw std::runtime_error(fmt::format(
        "{}: written by a calibration with other options ({}; now {}): give another record file, or the same options",
        path_.string(), lines[1].substr(10), fingerprint));
  const std::size_t fields = 3 + parameters + outputs;
  for (std::size_t k = 3; k < lines.size(); ++k) {
    const auto f = split(lines[k]);
    const bool last = k + 1 == lines.size();
    try {
      if (f.size() != fields || std::stoul(f[0]) != runs_.size() || (f[1] != "cheap" && f[1] != "expensive"))
        throw std::invalid_argument("fields");
      RecordedRun r;
      r.run.level = f[1] == "cheap" ? Level::cheap : Level::expensive;
      r.seed = std::stoull(f[2]);
      r.run.parameters.resize(parameters);
      r.run.outputs.resize(outputs);
      for (int a = 0; a < parameters; ++a) r.run.parameters(a) = std::stod(f[3 + a]);
      for (int j = 0; j < outputs; ++j) r.run.outputs(j) = std::stod(f[3 + parameters + j]);
      runs_.push_back(std::move(r));
    } catch (const std::exception&) {
      if (last && !last_complete) break;  // cut short by a kill: run again
      throw std::runtime_error(fmt::format("{}:{}: a malformed run line '{}' (expected {} fields: run, level, seed, "
                                           "parameters, outputs)", path_.string(), k + 1, lines[k], fields));
    }
  }
  if (!last_complete && !text.empty()) {
    // Rewrite without the cut line, so that the next append starts on a line of its own.
    std::ofstream out(path_, std::ios::trunc);
    for (std::size_t k = 0; k < 3 + runs_.size(); ++k) out << lines[k] << "\n";
  }
}

void LoopRecord::append(const RecordedRun& r) {
  std::string line = fmt::format("{},{},{}", runs_.size(), r.run.level == Level::cheap ? "cheap" : "expensive", r.seed);
  for (Eigen::Index a = 0; a < r.run.parameters.size(); ++a) line += fmt::format(",{:.17g}", r.run.parameters(a));
  for (Eigen::Index j = 0; j < r.run.outputs.size(); ++j) line += fmt::format(",{:.17g}", r.run.outputs(j));
  line += "\n";
  FILE* f = std::fopen(path_.c_str(), "a");
  if (!f) throw std::runtime_error(fmt::format("{}: cannot append to the calibration record", path_.string()));
  const bool written = std::fputs(line.c_str(), f) >= 0 && std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  std::fclose(f);
  if (!written) throw std::runtime_error(fmt::format("{}: writing a run to the calibration record failed", path_.string()));
  runs_.push_back(r);
}

}  // namespace mfdem::calibration
