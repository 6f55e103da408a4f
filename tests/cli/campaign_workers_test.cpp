// The workers of a campaign's --jobs (studies/cli/campaign_workers.hpp) end with the process that
// started them: a study stopped with `kill` once left its workers computing for an hour, unseen.
// Here a helper process starts a long-lived worker (/bin/sleep 60 in place of mfdem) and exits;
// the worker must be gone within 5 s, not 60.
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "studies/cli/campaign_workers.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

// Running: the process exists and is not a zombie waiting for a reaper.
bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string pid_field, name, state;
  if (!(stat >> pid_field >> name >> state)) return false;
  return state != "Z" && state != "X";
}

}  // namespace

TEST_CASE("a worker of --jobs ends when the process that started it ends", "[cli][campaign]") {
  const mfdem::test::TempDir dir;
  int channel[2];
  REQUIRE(pipe(channel) == 0);
  const pid_t helper = fork();
  REQUIRE(helper >= 0);
  if (helper == 0) {  // the study's first process: starts its worker, then is killed
    close(channel[0]);
    pid_t worker = -1;
    try {
      worker = mfdem::cli::spawn_worker({"60"}, dir.path() / "logs" / "worker-1.log", 1, "/bin/sleep");
    } catch (...) {
    }
    (void)!write(channel[1], &worker, sizeof worker);
    _exit(0);
  }
  close(channel[1]);
  pid_t worker = -1;
  REQUIRE(read(channel[0], &worker, sizeof worker) == static_cast<ssize_t>(sizeof worker));
  close(channel[0]);
  REQUIRE(worker > 0);
  waitpid(helper, nullptr, 0);
  const auto start = std::chrono::steady_clock::now();
  while (running(worker) && std::chrono::steady_clock::now() - start < std::chrono::seconds(5))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const bool still_running = running(worker);
  if (still_running) kill(worker, SIGKILL);  // leave nothing behind when the test fails
  CHECK_FALSE(still_running);
}

TEST_CASE("a worker of --jobs runs while the process that started it lives", "[cli][campaign]") {
  const mfdem::test::TempDir dir;
  const pid_t worker = mfdem::cli::spawn_worker({"0.2"}, dir.path() / "worker-1.log", 1, "/bin/sleep");
  REQUIRE(worker > 0);
  CHECK(running(worker));
  int status = -1;
  REQUIRE(waitpid(worker, &status, 0) == worker);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);  // ran to its end: not killed, not refused
}
