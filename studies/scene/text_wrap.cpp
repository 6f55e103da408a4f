#include "studies/scene/text_wrap.hpp"

#include <algorithm>

namespace mfdem::scene {

std::string wrap_text(std::string_view text, std::size_t width, std::string_view prefix) {
  std::string out;
  std::size_t line_length = 0;  // 0: no line started yet
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    const std::size_t end = std::min(text.find(' ', i), text.size());
    const std::string_view word = text.substr(i, end - i);
    if (line_length > 0 && line_length + 1 + word.size() <= width) {
      out += ' ';
      line_length += 1;
    } else {
      if (line_length > 0) out += '\n';
      out += prefix;
      line_length = prefix.size();
    }
    out += word;
    line_length += word.size();
    i = end;
  }
  return out;
}

}  // namespace mfdem::scene
