#include "studies/cli/python_figures.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

extern char** environ;

namespace mfdem::cli {
namespace {

std::string python_executable() {
  if (const char* chosen = std::getenv("MFDEM_PYTHON"); chosen && *chosen) return chosen;
  if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

}  // namespace

std::string figure_command(const std::string& module, const std::vector<std::string>& args) {
  std::string command = fmt::format("PYTHONPATH={} {} -m mfdem.{}", MFDEM_PYTHON_DIR, python_executable(), module);
  for (const auto& a : args) command += " " + a;
  return command;
}

bool draw_figures(const std::string& module, const std::vector<std::string>& args) {
  const std::string python = python_executable();
  std::vector<std::string> argv_text = {python, "-m", "mfdem." + module};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);

  // The environment with studies/python in front of any PYTHONPATH the user set.
  std::vector<std::string> env_text;
  std::string path = MFDEM_PYTHON_DIR;
  if (const char* given = std::getenv("PYTHONPATH"); given && *given) path += std::string(":") + given;
  env_text.push_back("PYTHONPATH=" + path);
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("PYTHONPATH=", 0) != 0) env_text.push_back(*e);
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);

  std::cout.flush();
  pid_t pid = 0;
  int status = 0;
  const int error = posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), envp.data());
  const bool ran = error == 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!ran)
    fmt::print(std::cerr,
               "mfdem: warning: the figures were not drawn ({}); the numbers are written. With Debian's "
               "python3-matplotlib and python3-h5py installed, draw them with:\n  {}\n",
               error != 0 ? fmt::format("cannot start {}", python) : "the Python module failed, see above",
               figure_command(module, args));
  return ran;
}

bool draw_study_figures(const std::string& module, const std::string& out, bool quiet) {
  std::vector<std::string> args = {out};
  if (quiet) args.push_back("--quiet");
  return draw_figures(module, args);
}

}  // namespace mfdem::cli
