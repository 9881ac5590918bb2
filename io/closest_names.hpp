// "Did you mean": the known names nearest to a mistyped one, by edit distance.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace tofcomp::io {

// The optimal string alignment distance: the fewest insertions, deletions, substitutions and
// swaps of two neighbouring characters that turn a into b ("evalute" → "evaluate": 1).
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidates nearest to typed, in their order, if they are near enough to be a typo of it:
// at most one edit per three characters (leading dashes not counted), and none for a name of
// fewer than three characters, where a single edit reaches too many names to be a hint.
std::vector<std::string> closest_names(std::string_view typed,
                                       const std::vector<std::string>& candidates);

}  // namespace tofcomp::io
