// Range and pointer checks shared by the kernels' input validation. They run once per
// shading call (a thousand times a frame), so a field's name is built only when its check
// fails: `name` is a string literal or a callable returning the name.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>

#include "shading/skin_params.h"

namespace pelt::shading::checks {

template <class Name>
std::string name_of(const Name& name) {
  if constexpr (std::is_invocable_v<const Name&>) return name();
  else return std::string(name);
}

inline std::string fmt(double v) { return std::to_string(v); }

template <class Name>
std::optional<ParamError> range(const Name& name, float v, double lo, double hi) {
  if (!std::isfinite(v)) return ParamError{name_of(name), "must be a finite number, got " + fmt(v)};
  if (v < lo || v > hi)
    return ParamError{name_of(name), "must be in [" + fmt(lo) + ", " + fmt(hi) + "], got " + fmt(v)};
  return std::nullopt;
}

template <class Name>
std::optional<ParamError> pointer(const Name& name, const void* p, bool required = true) {
  if (!p) {
    if (required) return ParamError{name_of(name), "must not be null"};
    return std::nullopt;
  }
  if ((reinterpret_cast<uintptr_t>(p) & 63u) != 0) return ParamError{name_of(name), "must be 64-byte aligned"};
  return std::nullopt;
}

}  // namespace pelt::shading::checks
