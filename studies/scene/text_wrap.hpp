#pragma once
// Paragraphs for people: long text broken at spaces so that a terminal or an editor shows it
// without side-scrolling.
#include <cstddef>
#include <string>
#include <string_view>

namespace mfdem::scene {

// `text` broken at spaces into lines of at most `width` characters, each line starting with
// `prefix` (counted in the width); a word longer than the room left keeps a line of its own.
// Runs of spaces collapse to one; joining the lines' words with single spaces gives the text back.
std::string wrap_text(std::string_view text, std::size_t width, std::string_view prefix = "");

}  // namespace mfdem::scene
