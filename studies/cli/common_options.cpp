#include "studies/cli/common_options.hpp"

#include <omp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

namespace mfdem::cli {

// --out must name a folder this process can write, or one it can make: checked before any work
// (a pack that fails to write its first checkpoint has already spent its deposition).
const CLI::Validator writable_folder(
    [](std::string& text) -> std::string {
      if (text.empty()) return "an empty path (expected the folder for the results)";
      std::error_code error;
      std::filesystem::path existing = std::filesystem::absolute(text, error);
      if (std::filesystem::exists(existing, error) && !std::filesystem::is_directory(existing, error))
        return "'" + text + "' is a file (expected a folder for the results)";
      while (!existing.empty() && !std::filesystem::exists(existing, error)) {
        if (existing == existing.parent_path()) break;
        existing = existing.parent_path();
      }
      if (!std::filesystem::is_directory(existing, error))
        return "'" + text + "': " + existing.string() + " is not a folder";
      // Make and remove a folder there: permission bits say nothing for root, and a read-only
      // or restricted file system (a mount, /sys) refuses only the attempt itself.
      const std::filesystem::path probe = existing / (".mfdem-write-probe-" + std::to_string(getpid()));
      if (mkdir(probe.c_str(), 0700) != 0)
        return "'" + text + "': cannot write into " + existing.string() + " (" + std::strerror(errno) + ")";
      rmdir(probe.c_str());
      return "";
    },
    "FOLDER");

void add_common_options(CLI::App& command, CommonOptions& options) {
  const CLI::Validator non_negative(
      [](const std::string& text) {
        return text.find_first_not_of("0123456789") == std::string::npos ? std::string()
                                                                          : "must be 0 (all cores) or a positive count";
      },
      "COUNT");
  command.add_option("--threads", options.threads, "OpenMP threads to use; 0 = all cores")
      ->check(non_negative)
      ->capture_default_str();
  // A function option runs only when --seed is given, which is what seed_given records. Digits
  // only: CLI11 would read "-1" as 2^64 - 1.
  const CLI::Validator seed_digits(
      [](const std::string& text) {
        return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos
                   ? std::string()
                   : "--seed " + text + ": expected a whole number >= 0";
      },
      "SEED");
  command
      .add_option_function<std::uint64_t>(
          "--seed",
          [&options](const std::uint64_t& seed) {
            options.seed = seed;
            options.seed_given = true;
          },
          "Random seed (packing, sampling); the same config and seed give the same results")
      ->check(seed_digits)
      ->default_str(std::to_string(options.seed));
  command.add_option("--out", options.out, "Directory for the results (out/ and scratch/ are ignored by git)")
      ->check(writable_folder)
      ->default_str(options.out.string());
  command.add_flag("--quiet,-q", options.quiet, "Print only warnings and errors");
}

CLI::Validator finite_positive(const std::string& unit) {
  return CLI::Validator(
      [unit](std::string& text) -> std::string {
        double x = 0.0;
        try {
          std::size_t used = 0;
          x = std::stod(text, &used);
          if (used != text.size()) return text + " is not a number (expected a finite number > 0, " + unit + ")";
        } catch (const std::exception&) {
          return text + " is not a number (expected a finite number > 0, " + unit + ")";
        }
        if (!std::isfinite(x) || x <= 0.0) return text + ": expected a finite number > 0 (" + unit + ")";
        return "";
      },
      "> 0");
}

void apply_thread_count(const CommonOptions& options) {
  omp_set_num_threads(options.threads > 0 ? options.threads : omp_get_num_procs());
}

}  // namespace mfdem::cli
