// Internal to the config checker: the parsed file shared by all Section views of it, with a record
// per opened table of the keys the program asked for (what Section::finish() compares against).
#pragma once

#include <cstddef>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace mfdem::config::detail {

struct Table {
  const toml::table* table;                  // points into Document::root
  std::string path;                          // dotted path, e.g. "materials.ballast"; "" at the top
  std::set<std::string, std::less<>> asked;  // keys read or probed, present in the file or not
  std::vector<std::size_t> opened;           // records of the sub-tables opened from this one
};

struct Document {
  std::string source;  // file name as given by the user, for messages
  toml::table root;
  std::vector<Table> tables;  // tables[0] is the top level

  // The record of `table` (created on first use), listed under `parent` for finish().
  std::size_t open(const toml::table& table, std::string path, std::size_t parent);
};

}  // namespace mfdem::config::detail
