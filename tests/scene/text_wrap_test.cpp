// wrap_text: prose broken at spaces into lines no wider than asked, losing no word.
#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "studies/scene/text_wrap.hpp"

namespace {

using mfdem::scene::wrap_text;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

}  // namespace

TEST_CASE("wrapped text keeps every word in order, each line within the width and prefixed", "[scene][text]") {
  const std::string text =
      "F(u): minus the sum of the stones' contact forces on the sleeper along the push (+x), mean "
      "over each record interval, against the sleeper's lateral displacement u.";
  const std::string wrapped = wrap_text(text, 40, "# ");
  const std::vector<std::string> lines = lines_of(wrapped);
  // The lines Python's textwrap.wrap(text, 40, initial_indent="# ", subsequent_indent="# ") gives.
  CHECK(lines == std::vector<std::string>{"# F(u): minus the sum of the stones'", "# contact forces on the sleeper along",
                                          "# the push (+x), mean over each record", "# interval, against the sleeper's",
                                          "# lateral displacement u."});
  std::string rejoined;
  for (const std::string& line : lines) {
    REQUIRE(line.size() <= 40);
    REQUIRE(line.rfind("# ", 0) == 0);
    rejoined += line.substr(2) + " ";
  }
  CHECK(words_of(rejoined) == words_of(text));
  // Greedy: no line could have taken the next line's first word.
  for (std::size_t k = 0; k + 1 < lines.size(); ++k)
    CHECK(lines[k].size() + 1 + words_of(lines[k + 1]).at(1).size() > 40);
}

TEST_CASE("a word longer than the width keeps a line of its own, and runs of spaces collapse", "[scene][text]") {
  CHECK(wrap_text("a  bb   supercalifragilistic cc", 6) == "a bb\nsupercalifragilistic\ncc");
  CHECK(wrap_text("", 10).empty());
  CHECK(wrap_text("short", 10, "> ") == "> short");
}
