#pragma once
// The run store: the folder every multi-run study (compare, statistics, calibration) writes
// into, one sub-folder per run, named by a key of what determines the run.
//
//   STORE/store.toml            format = "mfdem-store-1" and this layout, for a reader of the folder
//   STORE/runs/KEY/run.toml     the run's record (RunRecord): status "finished" or "failed", the
//                               message, the code revision, labels and numbers; beside it the
//                               run's own files (push.h5, push_summary.toml, packing.h5, ...)
//   STORE/shared/KEY/           what several runs start from (a seed's deposited bed), same rules
//   STORE/index.csv             one row per run, rebuilt from the run folders (never the only copy)
//   STORE/work/KEY.HOST.PID/    a run being computed (private to its process)
//   STORE/claims/KEY            who is computing KEY: "HOST PID" (advisory)
//
// Why no lock is needed, so that several processes (the --jobs of one machine, the jobs of a
// cluster sharing a file system) can fill one store: a run is computed in its process's own work
// folder and published by one rename(2) of that folder to runs/KEY, which is atomic: a reader
// sees no folder or the complete one. When two processes compute the same run, the second
// rename fails (the target exists and is not empty) and that process discards its copy: work may
// be done twice, nothing is lost or mixed. Claims (created with O_EXCL) only make double work
// rare: a process skips a run another live process has claimed; a claim whose process has died
// (same host) is taken over. A process killed at any moment leaves at most its work folders and
// claims, which the next study on that host clears.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mfdem::runs {

struct RunRecord {
  std::string key;
  std::string status;   // "finished" or "failed"
  std::string message;  // why it failed ("" when finished)
  std::string revision; // of the code that computed it
  // What the run is (model, seed, config) and what it gave; read back in name order.
  std::vector<std::pair<std::string, std::string>> labels;
  std::vector<std::pair<std::string, double>> numbers;

  bool finished() const { return status == "finished"; }
  std::optional<double> number(const std::string& name) const;
  std::string label(const std::string& name) const;  // "" when absent
};

// Writes and reads run.toml (numbers as the doubles they were, to 17 digits).
void write_record(const std::filesystem::path& file, const RunRecord& record);
RunRecord read_record(const std::filesystem::path& file);

// A key that names a folder: letters, digits and ._- kept, every other character '_'.
std::string folder_name(const std::string& text);

class RunStore {
 public:
  // Opens (creating) the store at `root`; throws std::runtime_error naming the folder when it
  // cannot be made or written, before any work.
  explicit RunStore(std::filesystem::path root);

  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path run_folder(const std::string& key) const { return root_ / "runs" / key; }
  std::filesystem::path shared_folder(const std::string& key) const { return root_ / "shared" / key; }

  // The published record of `key`, if any.
  std::optional<RunRecord> find(const std::string& key) const;
  // Whether `key` is published (finished or failed), without reading its record.
  bool has(const std::string& key) const;
  // How many of `keys` are published (finished or failed): folder lookups only.
  std::size_t count_published(const std::vector<std::string>& keys) const;

  enum class Outcome { computed, found, busy };
  // The run `key`: found when published; busy when another live process has claimed it;
  // otherwise computed: `compute(work)` fills the private folder `work` and returns the record
  // (its key and revision set here), which is written to work/run.toml before the folder is
  // published. An exception from compute is recorded as a failed run with its message (the
  // study goes on) unless it is one the caller must see (`rethrow` returns true for it).
  Outcome ensure(const std::string& key, const std::string& revision,
                 const std::function<RunRecord(const std::filesystem::path& work)>& compute,
                 const std::function<bool(const std::exception&)>& rethrow = {});

  // A shared input (a seed's deposited bed): its folder, computed by `make(work)` when absent.
  // While another live process makes it (its claim), this one waits for it: every run that
  // asks for it needs it.
  std::filesystem::path ensure_shared(const std::string& key,
                                      const std::function<void(const std::filesystem::path& work)>& make);

  // Moves a run published under `old_key` to `new_key` (a store made before its keys changed
  // form): its record's key rewritten in place, then the folder renamed whole, under new_key's
  // claim. Nothing when new_key is published or claimed, or old_key is not published.
  void adopt(const std::string& old_key, const std::string& new_key);

  // Every published record, in key order.
  std::vector<RunRecord> records() const;
  // index.csv from the run folders (written beside and renamed over the old one): key, status,
  // revision, every label, every number (columns in name order), message.
  void write_index() const;
  // Removes a failed run's folder so that it is computed again.
  void forget(const std::string& key) const;
  // The runs (and shared inputs, "shared.KEY") being computed now by any process, in key order:
  // their keys and private work folders.
  struct RunInProgress {
    std::string key;
    std::filesystem::path work;
  };
  std::vector<RunInProgress> in_progress() const;
  // Removes the work folders and claims this host's dead processes left; returns how many.
  int clear_abandoned() const;

 private:
  std::filesystem::path root_;
  std::filesystem::path work_folder(const std::string& key) const;
  bool claim(const std::string& key) const;
  void release(const std::string& key) const;
  void release_if_mine(const std::string& key) const;
  bool publish(const std::filesystem::path& work, const std::filesystem::path& target) const;
};

}  // namespace mfdem::runs
