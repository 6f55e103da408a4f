// Runs the real `mfdem` executable (MFDEM_EXECUTABLE, set by tests/CMakeLists.txt) through the
// shell and captures its exit status, standard output and standard error separately.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.hpp"

namespace mfdem::test {

struct Outcome {
  int status;  // exit status; -1 if the process did not exit normally (a crash)
  std::string out, err;
};

// Single quotes make the shell pass every byte literally; a quote inside is closed, escaped, reopened.
inline std::string shell_quoted(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Runs it in `working_directory` when given, else in the test's own.
inline Outcome run_mfdem(const std::vector<std::string>& arguments, const std::string& working_directory = {}) {
  const TempDir scratch;
  const auto err_file = scratch.path() / "stderr";
  std::string command = working_directory.empty() ? std::string() : "cd " + shell_quoted(working_directory) + " && ";
  command.append(shell_quoted(MFDEM_EXECUTABLE));
  // append() rather than " " + word: GCC 12 gives a false -Wrestrict on `literal + std::string&&`.
  for (const auto& argument : arguments) command.append(" ").append(shell_quoted(argument));
  command.append(" 2>").append(shell_quoted(err_file.string()));

  Outcome outcome{-1, {}, {}};
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return outcome;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) outcome.out.append(buffer, n);
  const int wait_status = ::pclose(pipe);
  if (wait_status != -1 && WIFEXITED(wait_status)) outcome.status = WEXITSTATUS(wait_status);
  std::ostringstream err;
  err << std::ifstream(err_file).rdbuf();
  outcome.err = err.str();
  return outcome;
}

}  // namespace mfdem::test
