#include "tools/io/suggest.h"

#include <algorithm>
#include <cctype>
#include <vector>

namespace pelt::io {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  // Three rows: the previous two are needed for the transposition case.
  const std::size_t w = b.size() + 1;
  std::vector<std::size_t> prev2(w), prev(w), cur(w);
  for (std::size_t j = 0; j < w; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j < w; ++j) {
      const bool same = lower(a[i - 1]) == lower(b[j - 1]);
      cur[j] = std::min({cur[j - 1] + 1, prev[j] + 1, prev[j - 1] + (same ? 0 : 1)});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1]))
        cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string nearest_name(std::string_view word, std::span<const std::string_view> candidates) {
  const std::size_t limit =
      word.size() <= 3 ? 1 : std::max<std::size_t>(2, std::min<std::size_t>(3, word.size() / 3));
  std::size_t best = limit + 1;
  std::string_view best_name;
  for (std::string_view c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best) {
      best = d;
      best_name = c;
    }
  }
  return std::string(best_name);
}

std::string did_you_mean(std::string_view word, std::span<const std::string_view> candidates) {
  const std::string n = nearest_name(word, candidates);
  return n.empty() ? std::string() : " (did you mean `" + n + "`?)";
}

}  // namespace pelt::io
