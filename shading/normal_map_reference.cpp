// The double-precision reference of normal_map.h, written for clarity: the specification the
// kernel is tested against, and what it evaluates its ill-conditioned lanes with. Doubles hold
// the products of any two floats exactly in range (denormals squared included), so no scaling
// is needed here.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "shading/normal_map.h"
#include "shading/param_checks.h"

namespace pelt::shading {
namespace {

struct D3 {
  double x, y, z;
};

double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 scale(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }

void throw_if(const std::optional<ParamError>& e) {
  if (e) throw std::invalid_argument(e->message());
}

}  // namespace

std::optional<ParamError> validate_batch(const NormalMapSoA& in, float* const out[3]) {
  static constexpr const char* kXyzw[4] = {"x", "y", "z", "w"};
  // Not alignment: the kernel loads unaligned, so a caller may hand it any sub-range.
  const auto named = [](const char* what, int c, const void* p) -> std::optional<ParamError> {
    if (p) return std::nullopt;
    return ParamError{std::string(what) + "[" + kXyzw[c] + "]", "must not be null"};
  };
  for (int c = 0; c < 3; ++c)
    if (auto e = named("normal", c, in.normal[c])) return e;
  for (int c = 0; c < 4; ++c)
    if (auto e = named("tangent", c, in.tangent[c])) return e;
  for (int c = 0; c < 3; ++c)
    if (!in.texel[c]) return ParamError{"texel[" + std::to_string(c) + "]", "must not be null"};
  if (!out) return ParamError{"out", "must not be null"};
  for (int c = 0; c < 3; ++c)
    if (auto e = named("out", c, out[c])) return e;
  return std::nullopt;
}

void perturb_normals_reference(const NormalMapSoA& in, float* const out[3]) {
  throw_if(validate_batch(in, out));
  for (size_t i = 0; i < in.n; ++i) {
    const D3 N{in.normal[0][i], in.normal[1][i], in.normal[2][i]};
    D3 T{in.tangent[0][i], in.tangent[1][i], in.tangent[2][i]};
    const double nn = dot(N, N);
    if (nn > 0.0) {
      const double k = dot(T, N) / nn;
      T = {T.x - k * N.x, T.y - k * N.y, T.z - k * N.z};
    }
    const double tl = std::sqrt(dot(T, T));
    D3 n = N;
    if (tl > 0.0) {
      const D3 Tu = scale(T, 1.0 / tl);
      const D3 Nu = nn > 0.0 ? scale(N, 1.0 / std::sqrt(nn)) : D3{0.0, 0.0, 0.0};
      const D3 B = scale(cross(Nu, Tu), in.tangent[3][i] < 0.0f ? -1.0 : 1.0);
      double m[3];
      for (int c = 0; c < 3; ++c) m[c] = 2.0 * std::clamp(double(in.texel[c][i]), 0.0, 1.0) - 1.0;
      n = {m[0] * Tu.x + m[1] * B.x + m[2] * Nu.x, m[0] * Tu.y + m[1] * B.y + m[2] * Nu.y,
           m[0] * Tu.z + m[1] * B.z + m[2] * Nu.z};
    }
    out[0][i] = float(n.x);
    out[1][i] = float(n.y);
    out[2][i] = float(n.z);
  }
}

}  // namespace pelt::shading
