#include "studies/runs/run_store.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <chrono>

namespace mfdem::runs {
namespace {

namespace fs = std::filesystem;
constexpr const char* kFormat = "mfdem-store-1";

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "host";
  std::string host = folder_name(name);
  std::replace(host.begin(), host.end(), '.', '-');  // the dots of work/KEY.HOST.PID separate its parts
  return host;
}

// The process a claim or a work folder belongs to.
struct Owner {
  std::string host;
  long pid = 0;
};

Owner this_process() { return {host_name(), static_cast<long>(getpid())}; }

// A work folder's name, KEY.HOST.PID (work_folder): its key and owner.
struct WorkName {
  std::string key;
  Owner owner;
};
std::optional<WorkName> parse_work_name(const std::string& name) {
  const auto last = name.rfind('.');
  if (last == std::string::npos || last == 0) return std::nullopt;
  const auto before = name.rfind('.', last - 1);
  if (before == std::string::npos) return std::nullopt;
  WorkName parsed{name.substr(0, before), {name.substr(before + 1, last - before - 1), 0}};
  try {
    parsed.owner.pid = std::stol(name.substr(last + 1));
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return parsed;
}

// A claim file holds "HOST PID".
Owner claim_owner(const fs::path& file) {
  Owner owner;
  std::ifstream(file) >> owner.host >> owner.pid;
  return owner;
}

// Of this host, and its process no longer runs.
bool dead_here(const Owner& o) {
  return o.host == host_name() && o.pid > 0 && kill(static_cast<pid_t>(o.pid), 0) != 0 && errno == ESRCH;
}

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// Writes `text` to `file` of the store at `root` whole: into this process's own file in work/,
// then renamed over `file`, so that a reader (another process opening the store) sees no file,
// the old one or the new one, never a part.
void write_whole(const fs::path& root, const fs::path& file, const std::string& text) {
  const fs::path partial = root / "work" / fmt::format("{}.{}.{}", file.filename().string(), host_name(), getpid());
  std::ofstream(partial) << text;
  fs::rename(partial, file);
}

std::string readme_text() {
  std::ostringstream out;
  out << "# An mfdem run store (studies/runs/run_store.hpp): runs/KEY/run.toml is each run's record,\n"
         "# index.csv a table of them rebuilt from the folders; work/ and claims/ hold runs in progress.\n"
      << toml::table{{"format", kFormat}} << "\n";
  return out.str();
}

}  // namespace

std::optional<double> RunRecord::number(const std::string& name) const {
  for (const auto& [n, v] : numbers)
    if (n == name) return v;
  return std::nullopt;
}

std::string RunRecord::label(const std::string& name) const {
  for (const auto& [n, v] : labels)
    if (n == name) return v;
  return {};
}

std::string folder_name(const std::string& text) {
  std::string out = text;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return out;
}

namespace {

std::string record_text(const RunRecord& r) {
  toml::table labels, numbers;
  for (const auto& [name, value] : r.labels) labels.insert_or_assign(name, value);
  for (const auto& [name, value] : r.numbers) numbers.insert_or_assign(name, value);  // shortest round-trip form
  const toml::table record{{"key", r.key},         {"status", r.status}, {"message", r.message},
                           {"revision", r.revision}, {"labels", labels},   {"numbers", numbers}};
  std::ostringstream out;
  out << "# mfdem run record (studies/runs/run_store.hpp)\n" << record << "\n";
  return out.str();
}

}  // namespace

void write_record(const fs::path& file, const RunRecord& r) {
  std::ofstream out(file);
  out << record_text(r);
  if (!out) throw std::runtime_error(fmt::format("{}: could not be written", file.string()));
}

RunRecord read_record(const fs::path& file) {
  toml::table t;
  try {
    t = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(fmt::format("{}: not a run record ({})", file.string(), e.description()));
  }
  RunRecord r;
  r.key = t["key"].value_or(std::string());
  r.status = t["status"].value_or(std::string());
  r.message = t["message"].value_or(std::string());
  r.revision = t["revision"].value_or(std::string());
  if (r.key.empty() || (r.status != "finished" && r.status != "failed"))
    throw std::runtime_error(fmt::format("{}: not a run record (key and status 'finished' or 'failed' expected)",
                                         file.string()));
  if (const auto* labels = t["labels"].as_table())
    for (const auto& [name, value] : *labels) r.labels.emplace_back(std::string(name.str()), value.value_or(std::string()));
  if (const auto* numbers = t["numbers"].as_table())
    for (const auto& [name, value] : *numbers) {
      // "nan" and "inf" are TOML floats too; an integer written without a point reads as one.
      const auto v = value.value<double>();
      r.numbers.emplace_back(std::string(name.str()), v ? *v : std::numeric_limits<double>::quiet_NaN());
    }
  return r;
}

RunStore::RunStore(fs::path root) : root_(std::move(root)) {
  if (root_.empty()) throw std::runtime_error("the store folder is empty: give --out DIR");
  std::error_code error;
  for (const char* sub : {"runs", "shared", "work", "claims"}) {
    fs::create_directories(root_ / sub, error);
    if (error)
      throw std::runtime_error(fmt::format("{}: cannot make the store's folder {} ({})", root_.string(), sub,
                                           error.message()));
  }
  const fs::path readme = root_ / "store.toml";
  if (fs::exists(readme)) {
    const std::string format = toml::parse_file(readme.string())["format"].value_or(std::string());
    if (format != kFormat)
      throw std::runtime_error(fmt::format("{}: format '{}', expected '{}' (a store of another mfdem version)",
                                           readme.string(), format, kFormat));
  } else {
    // Several processes may open a new store at once: each writes the same text whole.
    write_whole(root_, readme, readme_text());
  }
  // Writable, checked before any work: a study must not fail after its first run.
  const fs::path probe = root_ / "work" / fmt::format(".probe.{}.{}", host_name(), getpid());
  std::ofstream(probe) << "";
  if (!fs::exists(probe))
    throw std::runtime_error(fmt::format("{}: the store cannot be written to", root_.string()));
  fs::remove(probe);
}

fs::path RunStore::work_folder(const std::string& key) const {
  return root_ / "work" / fmt::format("{}.{}.{}", key, host_name(), getpid());
}

bool RunStore::has(const std::string& key) const { return fs::exists(run_folder(key) / "run.toml"); }

std::size_t RunStore::count_published(const std::vector<std::string>& keys) const {
  return static_cast<std::size_t>(std::count_if(keys.begin(), keys.end(), [&](const auto& k) { return has(k); }));
}

std::optional<RunRecord> RunStore::find(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return read_record(run_folder(key) / "run.toml");
}

bool RunStore::claim(const std::string& key) const {
  const fs::path file = root_ / "claims" / key;
  const Owner me = this_process();
  const std::string mine = fmt::format("{} {}\n", me.host, me.pid);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int fd = ::open(file.c_str(), O_CREAT | O_EXCL | O_WRONLY, 0644);
    if (fd >= 0) {
      const bool written = ::write(fd, mine.data(), mine.size()) == static_cast<ssize_t>(mine.size());
      ::close(fd);
      return written;
    }
    if (errno != EEXIST) return false;
    if (!dead_here(claim_owner(file))) return false;
    fs::remove(file);  // its process died: take it over (a race here costs a duplicate run at worst)
  }
  return false;
}

void RunStore::release_if_mine(const std::string& key) const {
  const Owner owner = claim_owner(root_ / "claims" / key), me = this_process();
  if (owner.host == me.host && owner.pid == me.pid) release(key);
}

void RunStore::release(const std::string& key) const {
  std::error_code ignored;
  fs::remove(root_ / "claims" / key, ignored);
}

bool RunStore::publish(const fs::path& work, const fs::path& target) const {
  std::error_code error;
  fs::rename(work, target, error);
  if (!error) return true;
  // Another process published it first (rename onto a non-empty folder fails): keep theirs.
  if (fs::exists(target)) {
    fs::remove_all(work);
    return false;
  }
  throw std::runtime_error(fmt::format("cannot publish {} as {} ({})", work.string(), target.string(),
                                       error.message()));
}

RunStore::Outcome RunStore::ensure(const std::string& key, const std::string& revision,
                                   const std::function<RunRecord(const fs::path&)>& compute,
                                   const std::function<bool(const std::exception&)>& rethrow) {
  if (has(key)) return Outcome::found;
  if (!claim(key)) return has(key) ? Outcome::found : Outcome::busy;
  // Published between our look and our claim by a process that has released it since.
  if (has(key)) {
    release(key);
    return Outcome::found;
  }
  const fs::path work = work_folder(key);
  fs::remove_all(work);
  fs::create_directories(work);
  RunRecord record;
  try {
    record = compute(work);
  } catch (const std::exception& e) {
    if (rethrow && rethrow(e)) {
      fs::remove_all(work);
      release(key);
      throw;
    }
    record = RunRecord{};
    record.status = "failed";
    record.message = e.what();
  }
  record.key = key;
  record.revision = revision;
  if (record.status.empty()) record.status = "finished";
  write_record(work / "run.toml", record);
  publish(work, run_folder(key));
  release(key);
  return Outcome::computed;
}

void RunStore::adopt(const std::string& old_key, const std::string& new_key) {
  if (old_key == new_key || has(new_key) || !has(old_key) || !claim(new_key)) return;
  if (!has(new_key) && has(old_key)) {
    RunRecord record = read_record(run_folder(old_key) / "run.toml");
    record.key = new_key;
    write_whole(root_, run_folder(old_key) / "run.toml", record_text(record));
    std::error_code ignored;  // another process moved it first: theirs stands
    fs::rename(run_folder(old_key), run_folder(new_key), ignored);
  }
  release(new_key);
}

fs::path RunStore::ensure_shared(const std::string& key, const std::function<void(const fs::path&)>& make) {
  const fs::path target = shared_folder(key);
  const std::string claim_key = "shared." + key;
  // Every run of a seed needs its deposition: wait while another live process makes it.
  while (!fs::exists(target / "complete") && !claim(claim_key))
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  if (fs::exists(target / "complete")) {
    release_if_mine(claim_key);
    return target;
  }
  const fs::path work = work_folder(claim_key);
  fs::remove_all(work);
  fs::create_directories(work);
  try {
    make(work);
  } catch (...) {
    fs::remove_all(work);
    release(claim_key);
    throw;
  }
  std::ofstream(work / "complete") << "";  // a marker inside the folder: it is published whole
  publish(work, target);
  release(claim_key);
  return target;
}

std::vector<RunRecord> RunStore::records() const {
  std::vector<RunRecord> all;
  std::set<fs::path> folders;
  for (const auto& entry : fs::directory_iterator(root_ / "runs"))
    if (entry.is_directory() && fs::exists(entry.path() / "run.toml")) folders.insert(entry.path());
  for (const auto& folder : folders) all.push_back(read_record(folder / "run.toml"));
  return all;
}

void RunStore::write_index() const {
  const std::vector<RunRecord> all = records();
  // Columns: the record's fields, then every label and number any run has, in first-seen order.
  std::vector<std::string> labels, numbers;
  for (const auto& r : all) {
    for (const auto& [name, value] : r.labels)
      if (std::find(labels.begin(), labels.end(), name) == labels.end()) labels.push_back(name);
    for (const auto& [name, value] : r.numbers)
      if (std::find(numbers.begin(), numbers.end(), name) == numbers.end()) numbers.push_back(name);
  }
  std::ostringstream out;
  out << "key,status,revision";
  for (const auto& name : labels) out << "," << csv_field(name);
  for (const auto& name : numbers) out << "," << csv_field(name);
  out << ",message\n";
  for (const auto& r : all) {
    out << csv_field(r.key) << "," << r.status << "," << csv_field(r.revision);
    for (const auto& name : labels) out << "," << csv_field(r.label(name));
    for (const auto& name : numbers) {
      const auto v = r.number(name);
      out << "," << (v ? fmt::format("{:.10g}", *v) : std::string());
    }
    out << "," << csv_field(r.message) << "\n";
  }
  write_whole(root_, root_ / "index.csv", out.str());
}

void RunStore::forget(const std::string& key) const { fs::remove_all(run_folder(key)); }

std::vector<RunStore::RunInProgress> RunStore::in_progress() const {
  std::vector<RunInProgress> found;
  std::error_code gone;  // a run may be published while the folder is read
  for (const auto& entry : fs::directory_iterator(root_ / "work", gone)) {
    if (const auto parsed = parse_work_name(entry.path().filename().string()))
      found.push_back({parsed->key, entry.path()});
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
  return found;
}

int RunStore::clear_abandoned() const {
  int cleared = 0;
  // work/KEY.HOST.PID and claims/KEY ("HOST PID" inside) of this host's dead processes.
  for (const auto& entry : fs::directory_iterator(root_ / "work")) {
    const auto parsed = parse_work_name(entry.path().filename().string());
    if (parsed && dead_here(parsed->owner)) cleared += fs::remove_all(entry.path()) > 0 ? 1 : 0;
  }
  for (const auto& entry : fs::directory_iterator(root_ / "claims"))
    if (dead_here(claim_owner(entry.path()))) cleared += fs::remove(entry.path()) ? 1 : 0;
  return cleared;
}

}  // namespace mfdem::runs
