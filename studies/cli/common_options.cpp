#include "studies/cli/common_options.hpp"

#include <omp.h>

namespace mfdem::cli {

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
      ->default_str(options.out.string());
  command.add_flag("--quiet,-q", options.quiet, "Print only warnings and errors");
}

void apply_thread_count(const CommonOptions& options) {
  omp_set_num_threads(options.threads > 0 ? options.threads : omp_get_num_procs());
}

}  // namespace mfdem::cli
