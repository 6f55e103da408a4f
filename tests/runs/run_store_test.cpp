// The run store (studies/runs/run_store.hpp): a run is computed once and published whole, a
// failure is recorded and does not stop the others, what a killed process left is cleared, two
// processes filling one store lose nothing, and the index is rebuilt from the folders alone.
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "studies/runs/run_store.hpp"
#include "tests/support/temp_dir.hpp"

using mfdem::runs::RunRecord;
using mfdem::runs::RunStore;
namespace fs = std::filesystem;

namespace {

RunRecord numbered(double value) {
  RunRecord r;
  r.labels = {{"model", "layer-by-height:h=0.1"}, {"seed", "3"}};
  r.numbers = {{"peak_force", value}, {"elements", 710}};
  return r;
}

std::string text_of(const fs::path& file) {
  std::stringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

// A process id that no process has: a child that exited and was reaped.
pid_t dead_pid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  return child;
}

std::string this_host() {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  std::string host = mfdem::runs::folder_name(name);
  std::replace(host.begin(), host.end(), '.', '-');
  return host;
}

}  // namespace

TEST_CASE("a run record reads back exactly as written", "[runs]") {
  const mfdem::test::TempDir dir;
  RunRecord r = numbered(0.1 + 0.2);  // 0.30000000000000004: needs all 17 digits
  r.key = "s1-all-clump";
  r.status = "failed";
  r.message = "unstable: \"energy grew\"\nat step 100, body 3";
  r.revision = "abc123";
  mfdem::runs::write_record(dir.path() / "run.toml", r);
  const RunRecord back = mfdem::runs::read_record(dir.path() / "run.toml");
  CHECK(back.key == r.key);
  CHECK(back.status == r.status);
  CHECK(back.message == r.message);
  CHECK(back.revision == r.revision);
  CHECK(back.labels == r.labels);  // read back in name order: model, seed
  REQUIRE(back.numbers.size() == 2);
  CHECK(back.number("peak_force") == 0.1 + 0.2);  // bitwise
  CHECK(back.number("elements") == 710.0);
}

TEST_CASE("a run is computed once: a second study finds it and computes nothing", "[runs]") {
  const mfdem::test::TempDir dir;
  RunStore store(dir.path() / "store");
  int calls = 0;
  const auto compute = [&](const fs::path& work) {
    ++calls;
    std::ofstream(work / "push.h5") << "data";
    return numbered(42.0);
  };
  CHECK(store.ensure("k1", "rev1", compute) == RunStore::Outcome::computed);
  CHECK(store.ensure("k1", "rev2", compute) == RunStore::Outcome::found);
  CHECK(calls == 1);
  RunStore reopened(dir.path() / "store");
  CHECK(reopened.ensure("k1", "rev2", compute) == RunStore::Outcome::found);
  CHECK(calls == 1);
  const auto record = reopened.find("k1");
  REQUIRE(record);
  CHECK(record->finished());
  CHECK(record->revision == "rev1");  // the code that computed it, not the one that found it
  CHECK(text_of(reopened.run_folder("k1") / "push.h5") == "data");
  CHECK(fs::is_empty(dir.path() / "store" / "work"));
  CHECK(fs::is_empty(dir.path() / "store" / "claims"));
}

TEST_CASE("a run under its key's earlier form is adopted whole: files, numbers, its record's new key", "[runs]") {
  const mfdem::test::TempDir dir;
  RunStore store(dir.path() / "store");
  const auto compute = [&](const fs::path& work) {
    std::ofstream(work / "push.h5") << "data";
    return numbered(42.0);
  };
  REQUIRE(store.ensure("old-form", "rev1", compute) == RunStore::Outcome::computed);
  store.adopt("old-form", "new-form");
  CHECK_FALSE(store.has("old-form"));
  const auto record = store.find("new-form");
  REQUIRE(record);
  CHECK(record->key == "new-form");
  CHECK(record->revision == "rev1");
  CHECK(record->number("peak_force") == 42.0);
  CHECK(text_of(store.run_folder("new-form") / "push.h5") == "data");
  int calls = 0;
  CHECK(store.ensure("new-form", "rev2", [&](const fs::path& w) { ++calls; return compute(w); }) ==
        RunStore::Outcome::found);
  CHECK(calls == 0);
  // Nothing to adopt, or the new key published already: nothing moves.
  store.adopt("absent", "other");
  CHECK_FALSE(store.has("other"));
  REQUIRE(store.ensure("second-old", "rev1", compute) == RunStore::Outcome::computed);
  store.adopt("second-old", "new-form");
  CHECK(store.has("second-old"));
  CHECK(store.find("new-form")->revision == "rev1");
  CHECK(fs::is_empty(dir.path() / "store" / "work"));
  CHECK(fs::is_empty(dir.path() / "store" / "claims"));
}

TEST_CASE("a failing run is recorded with its message and the others complete", "[runs]") {
  const mfdem::test::TempDir dir;
  RunStore store(dir.path() / "store");
  for (int k = 0; k < 3; ++k)
    store.ensure(fmt::format("k{}", k), "rev", [&](const fs::path&) {
      if (k == 1) throw std::runtime_error("unstable: the re-settling blew up");
      return numbered(k);
    });
  const auto all = store.records();
  REQUIRE(all.size() == 3);
  CHECK(all[0].finished());
  CHECK(all[1].status == "failed");
  CHECK(all[1].message == "unstable: the re-settling blew up");
  CHECK(all[2].finished());
  // An error the caller must see (here: a refused input) is not recorded, and stops the study.
  const auto refused = [](const std::exception& e) { return std::string(e.what()).find("refused") == 0; };
  CHECK_THROWS_WITH(store.ensure("k3", "rev", [](const fs::path&) -> RunRecord { throw std::runtime_error("refused"); },
                                 refused),
                    "refused");
  CHECK_FALSE(store.find("k3"));
  CHECK(fs::is_empty(dir.path() / "store" / "work"));
  // A failed run is computed again once forgotten.
  store.forget("k1");
  CHECK(store.ensure("k1", "rev", [](const fs::path&) { return numbered(1.0); }) == RunStore::Outcome::computed);
  CHECK(store.find("k1")->finished());
}

TEST_CASE("what a killed process left is cleared, and its run computed again", "[runs]") {
  const mfdem::test::TempDir dir;
  RunStore store(dir.path() / "store");
  const pid_t gone = dead_pid();
  const fs::path work = dir.path() / "store" / "work" / fmt::format("k1.{}.{}", this_host(), gone);
  fs::create_directories(work);
  std::ofstream(work / "push.h5") << "half";
  std::ofstream(dir.path() / "store" / "claims" / "k1") << this_host() << " " << gone << "\n";
  // A live claim (this process's parent, which runs) is left alone, and its run reported busy.
  std::ofstream(dir.path() / "store" / "claims" / "k2") << this_host() << " " << getppid() << "\n";
  CHECK(store.ensure("k2", "rev", [](const fs::path&) { return numbered(2.0); }) == RunStore::Outcome::busy);
  CHECK(store.clear_abandoned() == 2);
  CHECK_FALSE(fs::exists(work));
  CHECK(fs::exists(dir.path() / "store" / "claims" / "k2"));
  CHECK(store.ensure("k1", "rev", [](const fs::path&) { return numbered(1.0); }) == RunStore::Outcome::computed);
  // A dead process's claim is taken over without clearing first.
  std::ofstream(dir.path() / "store" / "claims" / "k3") << this_host() << " " << gone << "\n";
  CHECK(store.ensure("k3", "rev", [](const fs::path&) { return numbered(3.0); }) == RunStore::Outcome::computed);
}

TEST_CASE("two processes filling one store lose nothing and publish every run whole", "[runs]") {
  const mfdem::test::TempDir dir;
  const fs::path root = dir.path() / "store";
  RunStore(root).write_index();  // made before the writers start
  constexpr int kRuns = 24;
  // Each writer walks the same keys (one forwards, one backwards, so they meet in the middle),
  // taking a few milliseconds per run, and writes a file of 64 kB it checks is whole.
  const auto writer = [&](bool backwards) {
    RunStore store(root);
    for (int i = 0; i < kRuns; ++i) {
      const int k = backwards ? kRuns - 1 - i : i;
      store.ensure(fmt::format("k{:02}", k), fmt::format("pid{}", getpid()), [&](const fs::path& work) {
        std::ofstream(work / "push.h5") << std::string(65536, static_cast<char>('a' + k % 26));
        std::this_thread::sleep_for(std::chrono::milliseconds(3));
        return numbered(k);
      });
    }
  };
  pid_t children[2];
  for (int w = 0; w < 2; ++w) {
    children[w] = fork();
    if (children[w] == 0) {
      try {
        writer(w == 1);
      } catch (...) {
        _exit(1);
      }
      _exit(0);
    }
  }
  for (pid_t child : children) {
    int status = 0;
    waitpid(child, &status, 0);
    CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 0));
  }
  RunStore store(root);
  const auto all = store.records();
  REQUIRE(all.size() == kRuns);
  for (int k = 0; k < kRuns; ++k) {
    CHECK(all[k].key == fmt::format("k{:02}", k));
    CHECK(all[k].number("peak_force") == double(k));
    CHECK(text_of(store.run_folder(all[k].key) / "push.h5") == std::string(65536, static_cast<char>('a' + k % 26)));
  }
  CHECK(fs::is_empty(root / "work"));
  CHECK(fs::is_empty(root / "claims"));
  // The index, rebuilt from the folders: one row per run (and the header), whatever it held.
  fs::remove(root / "index.csv");
  store.write_index();
  const std::string index = text_of(root / "index.csv");
  CHECK(std::count(index.begin(), index.end(), '\n') == kRuns + 1);
  CHECK(index.rfind("key,status,revision,model,seed,elements,peak_force,message\n", 0) == 0);
}

TEST_CASE("processes opening one new store at once all open it", "[runs]") {
  // The tasks of a job array start together on an empty --out: each must find store.toml absent
  // or whole, never empty (a store half-written by another reads as "format ''"). 12 processes
  // open the same 40 new stores in the same order, so they meet at every one.
  const mfdem::test::TempDir dir;
  constexpr int kProcesses = 12, kStores = 40;
  std::vector<pid_t> children;
  for (int p = 0; p < kProcesses; ++p) {
    const pid_t child = fork();
    if (child == 0) {
      try {
        for (int k = 0; k < kStores; ++k) RunStore(dir.path() / fmt::format("store{:02}", k));
      } catch (...) {
        _exit(1);
      }
      _exit(0);
    }
    children.push_back(child);
  }
  int opened = 0;
  for (pid_t child : children) {
    int status = 0;
    waitpid(child, &status, 0);
    opened += WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 1 : 0;
  }
  CHECK(opened == kProcesses);
  for (int k = 0; k < kStores; ++k) CHECK_NOTHROW(RunStore(dir.path() / fmt::format("store{:02}", k)));
}

TEST_CASE("a store that cannot be made is refused before any work, naming the folder", "[runs]") {
  const mfdem::test::TempDir dir;
  std::ofstream(dir.path() / "file") << "";
  CHECK_THROWS_WITH(RunStore(dir.path() / "file" / "store"),
                    Catch::Contains((dir.path() / "file" / "store").string()) && Catch::Contains("cannot make"));
  CHECK_THROWS_WITH(RunStore(""), Catch::Contains("--out"));
}
