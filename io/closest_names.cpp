// Edit distance and the nearest names (io/closest_names.hpp).
#include "io/closest_names.hpp"

#include <algorithm>

namespace tofcomp::io {

namespace {

// Names shorter than this get no suggestion; longer ones tolerate one edit per this many
// characters.
constexpr std::size_t kCharactersPerEdit = 3;

std::string_view without_dashes(std::string_view name) {
  const std::size_t first = name.find_first_not_of('-');
  return first == std::string_view::npos ? std::string_view() : name.substr(first);
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // d[i][j]: the distance between a's first i characters and b's first j.
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

std::vector<std::string> closest_names(std::string_view typed,
                                       const std::vector<std::string>& candidates) {
  const std::size_t length = without_dashes(typed).size();
  if (length < kCharactersPerEdit) return {};
  std::size_t best = length / kCharactersPerEdit;  // the most edits a typo may have
  std::vector<std::string> closest;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(typed, candidate);
    if (distance == 0 || distance > best) continue;
    if (distance < best) closest.clear();
    best = distance;
    closest.push_back(candidate);
  }
  return closest;
}

}  // namespace tofcomp::io
