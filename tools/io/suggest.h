// "Did you mean" support for error messages: the nearest known name to a misspelling.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace pelt::io {

// Edit distance with insertions, deletions, substitutions and transpositions of two
// adjacent letters, each cost 1 (optimal string alignment), ASCII case-insensitive:
// the usual typos (`widht`, `Fovy_deg`) are one edit away.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word` when it is close enough to be a plausible typo:
// distance <= 1 for words of up to 3 letters, else <= max(2, min(3, |word| / 3)) (ties: the first candidate listed). Returns an
// empty string when nothing is close.
std::string nearest_name(std::string_view word, std::span<const std::string_view> candidates);

// " (did you mean `x`?)" for the nearest candidate, or "" when there is none.
std::string did_you_mean(std::string_view word, std::span<const std::string_view> candidates);

}  // namespace pelt::io
