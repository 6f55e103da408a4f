#include "studies/config/document.hpp"

namespace mfdem::config::detail {

std::size_t Document::open(const toml::table& table, std::string path, std::size_t parent) {
  for (std::size_t i = 0; i < tables.size(); ++i)
    if (tables[i].table == &table) return i;
  tables.push_back(Table{&table, std::move(path), {}, {}});
  const std::size_t id = tables.size() - 1;
  tables[parent].opened.push_back(id);
  return id;
}

}  // namespace mfdem::config::detail
