#include "studies/cli/campaign_workers.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <chrono>
#include <stdexcept>
#include <thread>

#include "studies/campaigns/push_runs.hpp"

extern char** environ;

namespace mfdem::cli {

namespace fs = std::filesystem;

pid_t spawn_worker(const std::vector<std::string>& args, const fs::path& log, int number) {
  std::vector<std::string> all = args;
  all.insert(all.begin(), "mfdem");
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  fs::create_directories(log.parent_path());
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, "/proc/self/exe", &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (error != 0) throw std::runtime_error(fmt::format("could not start worker {} of --jobs ({})", number, error));
  return pid;
}

void wait_for_workers(const std::vector<pid_t>& workers, const std::function<void()>& poll) {
  for (std::size_t finished = 0; finished < workers.size();) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    finished = 0;
    for (pid_t w : workers) finished += kill(w, 0) != 0 || waitpid(w, nullptr, WNOHANG) == w ? 1 : 0;
    if (poll) poll();
  }
  for (pid_t w : workers) waitpid(w, nullptr, 0);
}

void run_with_jobs(int jobs, const std::vector<std::string>& args, const fs::path& out,
                   const campaigns::RunSlice& own, const std::function<void(const campaigns::RunSlice&)>& run,
                   const std::function<void()>& poll) {
  if (jobs <= 1) {
    run(own);
    return;
  }
  std::vector<pid_t> workers;
  for (int k = 1; k < jobs; ++k) {
    std::vector<std::string> worker = args;
    worker.insert(worker.end(), {"--slice", fmt::format("{}/{}", k, jobs), "--worker", "--quiet"});
    workers.push_back(spawn_worker(worker, out / "logs" / fmt::format("worker-{}.log", k), k));
  }
  run({0, static_cast<std::size_t>(jobs)});
  wait_for_workers(workers, poll);
  run({});
}

void add_jobs_options(CLI::App& command, int& jobs, bool& worker) {
  command.add_option("--jobs", jobs, "Runs computed at once, each a process of --threads threads (2 cores: 2 jobs of "
                                     "1 thread run small beds fastest)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  command.add_flag("--worker", worker)->group("");  // a process of --jobs: runs its slice, writes no tables
}

std::string campaign_progress_detail(const runs::RunStore& store, const std::string& counted) {
  const std::string running = campaigns::running_runs(store);
  return running.empty() ? counted : fmt::format("{}; running: {}", counted, running);
}

}  // namespace mfdem::cli
