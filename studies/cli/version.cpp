#include "studies/cli/version.hpp"

#include <omp.h>

#include <fmt/format.h>

#include "mfdem_revision.hpp"  // generated at build time: MFDEM_GIT_REVISION

namespace mfdem::cli {

std::string version() { return MFDEM_VERSION; }

std::string git_revision() { return MFDEM_GIT_REVISION; }

std::string version_line() { return fmt::format("mfdem {} (git {})", version(), git_revision()); }

std::string build_report() {
#ifdef NDEBUG
  constexpr const char* assertions = "off (optimised build)";
#else
  constexpr const char* assertions = "on (debug build)";
#endif
#if defined(__clang__)
  constexpr const char* compiler = "clang " __clang_version__;
#else
  constexpr const char* compiler = "GCC " __VERSION__;
#endif
#if defined(__SANITIZE_ADDRESS__)
  constexpr const char* sanitizers = "address, undefined";
#else
  constexpr const char* sanitizers = "none";
#endif
  return fmt::format(
      "{}\n"
      "compiler:   {}\n"
      "assertions: {}\n"
      "sanitizers: {}\n"
      "OpenMP:     version {}, up to {} threads on {} cores\n",
      version_line(), compiler, assertions, sanitizers, _OPENMP, omp_get_max_threads(), omp_get_num_procs());
}

}  // namespace mfdem::cli
