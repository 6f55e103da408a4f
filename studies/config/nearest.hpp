// Spelling suggestions for unknown keys and choices ("did you mean 'materials'?").
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mfdem::config {

// Optimal-string-alignment distance: insertions, deletions, substitutions and swaps of two
// neighbouring letters each cost 1, so the common typo "materails" is 1 away from "materials".
// Letters are compared without regard to case.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate nearest to word, if it is close enough to be a plausible typo: at most 2 edits,
// and fewer than half of the word's letters changed. Ties go to the first candidate.
std::optional<std::string> nearest(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace mfdem::config
