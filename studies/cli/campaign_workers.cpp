#include "studies/cli/campaign_workers.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "studies/campaigns/push_runs.hpp"

extern char** environ;

namespace mfdem::cli {

namespace fs = std::filesystem;

pid_t spawn_worker(const std::vector<std::string>& args, const fs::path& log, int number, const char* executable) {
  std::vector<std::string> all = args;
  all.insert(all.begin(), "mfdem");
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  fs::create_directories(log.parent_path());
  const std::string log_name = log.string();
  const pid_t parent = getpid();
  // fork and exec rather than posix_spawn, for the one call between them: the worker gets SIGTERM
  // when this process ends, however it ends (a `kill` of the study once left its workers computing
  // for an hour, unseen). Only async-signal-safe calls follow the fork.
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(fmt::format("could not start worker {} of --jobs (fork: errno {})", number, errno));
  if (pid == 0) {
    if (prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || getppid() != parent) _exit(127);  // the parent already gone
    const int fd = open(log_name.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0) _exit(127);
    close(fd);
    execve(executable, argv.data(), environ);
    _exit(127);
  }
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
