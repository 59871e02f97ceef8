// Fur lighting kernels (shading/fur_lighting.h) against their double-precision references, for
// every compiled Highway target: a million random lanes, the hard cases the header names, the
// model's properties, and the validation messages.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cfloat>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "shading/fur_lighting.h"
#include "tests/shading/batch_harness.h"
#include "tests/shading/random_inputs.h"

namespace pelt::shading {
namespace fur_lighting_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

using testing::Buffer;
using testing::close_enough;
using testing::for_each_target;
using testing::make_buffer;

// pos, tangent, normal (3 each), height, texel (4): 14 arrays of n floats.
struct Inputs {
  size_t n;
  std::vector<Buffer> a;
  explicit Inputs(size_t n_) : n(n_) {
    for (int k = 0; k < 14; ++k) a.push_back(make_buffer(n));
  }
  float* pos(int c) { return a[c].get(); }
  float* tangent(int c) { return a[3 + c].get(); }
  float* normal(int c) { return a[6 + c].get(); }
  float* height() { return a[9].get(); }
  float* texel(int c) { return a[10 + c].get(); }
  FurSurfaceSoA soa() {
    FurSurfaceSoA s{};
    s.n = n;
    for (int c = 0; c < 3; ++c) {
      s.pos[c] = pos(c);
      s.tangent[c] = tangent(c);
      s.normal[c] = normal(c);
    }
    s.height = height();
    for (int c = 0; c < 4; ++c) s.texel[c] = texel(c);
    return s;
  }
  void set3(float* (Inputs::*field)(int), size_t i, float x, float y, float z) {
    (this->*field)(0)[i] = x;
    (this->*field)(1)[i] = y;
    (this->*field)(2)[i] = z;
  }
};

struct Outputs {
  size_t n;
  std::vector<Buffer> a;
  explicit Outputs(size_t n_) : n(n_) {
    for (int k = 0; k < 4; ++k) a.push_back(make_buffer(n));
  }
  FurOutSoA soa() { return FurOutSoA{{a[0].get(), a[1].get(), a[2].get(), a[3].get()}}; }
  float at(int k, size_t i) const { return a[k][i]; }
};

// Every output of `got` finite, non-negative and within the tolerance of `ref`; reports at most
// a few mismatches, with `describe(lane)`.
void expect_close(const Outputs& ref, const Outputs& got, const std::function<std::string(size_t)>& describe = {}) {
  size_t bad = 0;
  for (int k = 0; k < 4; ++k)
    for (size_t i = 0; i < ref.n; ++i) {
      const double r = ref.at(k, i), g = got.at(k, i);
      if (std::isfinite(g) && g >= 0.0 && close_enough(r, g)) continue;
      if (bad++ < 5)
        ADD_FAILURE() << "lane " << i << " channel " << k << ": kernel " << g << " reference " << r
                      << (describe ? std::string(" ").append(describe(i)) : std::string());
    }
  EXPECT_EQ(bad, 0u);
}

using testing::random_eye;
using testing::random_lights;
using testing::Rng;

FurLightParams random_params(Rng& r) {
  FurLightParams p;
  p.ambient_occlusion_root = r.uni(0, 1);
  p.diffuse = r.uni(0, 2);
  p.specular = r.uni(0, 2);
  // Integer exponents take the repeated-squaring path, the others exp(log); both over [1, 512].
  p.shininess = r.logu(1, 512);
  if (r.pick(2) == 0) p.shininess = std::round(p.shininess);
  if (r.pick(8) == 0) p.shininess = 512.0f;
  p.backlight_wrap = r.pick(4) == 0 ? 0.0f : r.uni(0, 1);
  return p;
}

void random_surface(Rng& r, Inputs& in) {
  for (size_t i = 0; i < in.n; ++i) {
    float t[3], nrm[3];
    r.unit(t);
    r.unit(nrm);
    const float tl = r.logu(1e-3f, 1e3f), nl = r.logu(1e-3f, 1e3f);
    for (int c = 0; c < 3; ++c) {
      in.pos(c)[i] = r.uni(-1, 1);
      in.tangent(c)[i] = t[c] * tl;
      in.normal(c)[i] = nrm[c] * nl;
    }
    in.height()[i] = r.uni(-0.2f, 1.2f);  // outside [0, 1]: clamped
    for (int c = 0; c < 4; ++c) in.texel(c)[i] = r.uni(-0.1f, 1.1f);
  }
}

std::string describe_lane(Inputs& in, size_t i, const FurLightParams& p, const std::vector<Light>& lights,
                          const float eye[3]) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "pos %.9g %.9g %.9g t %.9g %.9g %.9g n %.9g %.9g %.9g h %.9g eye %.9g %.9g %.9g shin %.9g wrap %.9g",
                in.pos(0)[i], in.pos(1)[i], in.pos(2)[i], in.tangent(0)[i], in.tangent(1)[i], in.tangent(2)[i],
                in.normal(0)[i], in.normal(1)[i], in.normal(2)[i], in.height()[i], eye[0], eye[1], eye[2],
                p.shininess, p.backlight_wrap);
  std::string s = buf;
  for (const Light& l : lights) {
    std::snprintf(buf, sizeof buf, " | L%d %.9g %.9g %.9g", int(l.type), l.vec[0], l.vec[1], l.vec[2]);
    s += buf;
  }
  return s;
}

TEST(FurLighting, MatchesReferenceOnAMillionRandomInputs) {
  Rng r(0xf0f1);
  const size_t n = 16384;
  const int batches = 64;  // 1,048,576 lanes, each batch with its own parameters, lights and eye
  Inputs in(n);
  for (int b = 0; b < batches; ++b) {
    const FurLightParams p = random_params(r);
    const std::vector<Light> lights = random_lights(r);
    float eye[3];
    random_eye(r, eye);
    random_surface(r, in);
    Outputs ref(n);
    shade_fur_reference(p, lights.data(), lights.size(), eye, in.soa(), ref.soa());
    SCOPED_TRACE("batch " + std::to_string(b));
    for_each_target([&](int64_t) {
      Outputs got(n);
      shade_fur(p, lights.data(), lights.size(), eye, in.soa(), got.soa());
      expect_close(ref, got, [&](size_t i) { return describe_lane(in, i, p, lights, eye); });
    });
  }
}

// One lane per case; lanes past the cases repeat a plain fragment.
TEST(FurLighting, HardCasesMatchReferenceAndStayFinite) {
  const size_t n = 64;
  Inputs in(n);
  const float eye[3] = {0.0f, 0.0f, 5.0f};
  const float dir[3] = {0.3f, 0.8f, 0.5f};
  const double dlen = std::sqrt(0.09 + 0.64 + 0.25);
  const float L[3] = {float(0.3 / dlen), float(0.8 / dlen), float(0.5 / dlen)};
  const float point[3] = {0.25f, -0.5f, 0.75f};
  for (size_t i = 0; i < n; ++i) {
    in.set3(&Inputs::pos, i, 0.1f, 0.2f, 0.3f);
    in.set3(&Inputs::tangent, i, 0.0f, 1.0f, 0.2f);
    in.set3(&Inputs::normal, i, 0.0f, 0.0f, 1.0f);
    in.height()[i] = 0.5f;
    for (int c = 0; c < 4; ++c) in.texel(c)[i] = 0.25f * float(c + 1);
  }
  size_t k = 0;
  in.set3(&Inputs::tangent, k++, 0.0f, 0.0f, 0.0f);                   // zero tangent
  in.set3(&Inputs::tangent, k++, 1e-40f, -1e-40f, 1e-41f);             // denormal tangent
  in.set3(&Inputs::tangent, k++, 1e-20f, 2e-20f, 0.0f);                // tiny tangent
  in.set3(&Inputs::tangent, k++, 1e20f, 3e20f, -2e20f);                // |t|^2 overflows float
  in.set3(&Inputs::normal, k++, 0.0f, 0.0f, 0.0f);                     // zero normal
  in.set3(&Inputs::normal, k++, 1e-40f, 0.0f, 1e-40f);                 // denormal normal
  in.set3(&Inputs::normal, k, 0.0f, 0.0f, 0.0f);                       // zero tangent and normal
  in.set3(&Inputs::tangent, k++, 0.0f, 0.0f, 0.0f);
  in.set3(&Inputs::pos, k++, point[0], point[1], point[2]);            // point light at the fragment
  in.set3(&Inputs::pos, k, point[0], point[1], point[2]);              // ... with a zero normal
  in.set3(&Inputs::normal, k++, 0.0f, 0.0f, 0.0f);
  in.set3(&Inputs::pos, k++, eye[0], eye[1], eye[2]);                  // eye at the fragment: V = 0
  in.set3(&Inputs::pos, k, eye[0], eye[1], eye[2]);                    // V = 0, zero t and n
  in.set3(&Inputs::normal, k, 0.0f, 0.0f, 0.0f);
  in.set3(&Inputs::tangent, k++, 0.0f, 0.0f, 0.0f);
  in.set3(&Inputs::tangent, k++, L[0], L[1], L[2]);                    // T parallel to L
  in.set3(&Inputs::tangent, k++, -2 * L[0], -2 * L[1], -2 * L[2]);    // T antiparallel to L
  {
    // T parallel to H = L + V for the fragment at pos (0.1, 0.2, 0.3).
    const double v[3] = {eye[0] - 0.1, eye[1] - 0.2, eye[2] - 0.3};
    const double vl = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double h[3] = {L[0] + v[0] / vl, L[1] + v[1] / vl, L[2] + v[2] / vl};
    in.set3(&Inputs::tangent, k++, float(h[0]), float(h[1]), float(h[2]));
  }
  {
    // L = -V exactly: the fragment straight behind the light's direction (no half vector).
    in.set3(&Inputs::pos, k, 0.0f, 0.0f, 5.0f - 2.0f);  // V = +z
    in.set3(&Inputs::normal, k, 0.0f, 0.0f, -1.0f);     // faces the light (-z)
    k++;
  }
  in.height()[k++] = -3.0f;
  in.height()[k++] = 7.0f;
  for (int c = 0; c < 4; ++c) in.texel(c)[k] = -1.0f;
  k++;
  for (int c = 0; c < 4; ++c) in.texel(c)[k] = 5.0f;
  k++;
  in.set3(&Inputs::pos, k++, 1e30f, -1e30f, 3e38f);                    // far: eye - pos overflows |.|^2
  in.set3(&Inputs::normal, k++, 3e38f, 3e38f, 0.0f);                   // |n|^2 overflows
  in.set3(&Inputs::tangent, k++, 1.0f, 1e-30f, 0.0f);                  // nearly axis-aligned
  ASSERT_LT(k, n);

  const float minus_z[3] = {0.0f, 0.0f, -1.0f};
  std::vector<std::vector<Light>> setups;
  auto light = [](Light::Type t, const float v[3], float r, float g, float b) {
    Light l{};
    l.type = t;
    for (int c = 0; c < 3; ++c) l.vec[c] = v[c];
    l.color[0] = r;
    l.color[1] = g;
    l.color[2] = b;
    return l;
  };
  setups.push_back({light(Light::Type::Directional, dir, 1, 0.9f, 0.8f)});
  setups.push_back({light(Light::Type::Directional, minus_z, 1, 1, 1)});  // the L = -V lane
  setups.push_back({light(Light::Type::Point, point, 2, 1, 0.5f), light(Light::Type::Ambient, dir, 0.2f, 0.2f, 0.3f)});
  setups.push_back({light(Light::Type::Point, eye, 1, 1, 1), light(Light::Type::Directional, dir, 0.5f, 0.5f, 0.5f),
                    light(Light::Type::Point, point, 1, 0, 1)});
  for (float shininess : {1.0f, 2.0f, 40.0f, 41.0f, 77.7f, 512.0f}) {
    FurLightParams p;
    p.shininess = shininess;
    for (float wrap : {0.0f, 0.25f, 1.0f}) {
      p.backlight_wrap = wrap;
      for (const std::vector<Light>& lights : setups) {
        Outputs ref(n);
        shade_fur_reference(p, lights.data(), lights.size(), eye, in.soa(), ref.soa());
        SCOPED_TRACE("shininess " + std::to_string(shininess) + " wrap " + std::to_string(wrap) + " lights " +
                     std::to_string(lights.size()));
        for_each_target([&](int64_t) {
          Outputs got(n);
          shade_fur(p, lights.data(), lights.size(), eye, in.soa(), got.soa());
          expect_close(ref, got);
        });
      }
    }
  }
}

// A batch of random fragments lit by `lights`, shaded for every target; `check(ref inputs,
// outputs)` runs on each target's outputs.
struct PropertyScene {
  Rng r{0x9e0};
  Inputs in{4096};
  float eye[3] = {1.0f, 2.0f, 6.0f};
  PropertyScene() { random_surface(r, in); }
};

TEST(FurLighting, AlphaPassesThroughUnchanged) {
  PropertyScene s;
  for (size_t i = 0; i < s.in.n; ++i) s.in.texel(3)[i] = s.r.uni(0, 1);
  s.in.texel(3)[0] = 0.0f;
  s.in.texel(3)[1] = 1.0f;
  s.in.texel(3)[2] = 1e-40f;  // a denormal alpha is still in [0, 1]
  const std::vector<Light> lights = random_lights(s.r);
  for_each_target([&](int64_t) {
    Outputs got(s.in.n);
    shade_fur(FurLightParams{}, lights.data(), lights.size(), s.eye, s.in.soa(), got.soa());
    for (size_t i = 0; i < s.in.n; ++i) ASSERT_EQ(got.at(3, i), s.in.texel(3)[i]) << "lane " << i;
    const float dir[3] = {0.3f, 0.8f, 0.5f};
    shade_fur_match_llvmpipe(dir, s.in.soa(), got.soa());
    for (size_t i = 0; i < s.in.n; ++i) ASSERT_EQ(got.at(3, i), s.in.texel(3)[i]) << "lane " << i;
  });
}

TEST(FurLighting, TangentParallelToLightGivesNoDiffuse) {
  PropertyScene s;
  FurLightParams p;
  p.specular = 0.0f;
  p.backlight_wrap = 1.0f;  // the wrap factor is then 1: only the tangent term can vanish
  Rng r(0x7a11);
  for (int trial = 0; trial < 16; ++trial) {
    Light l{};
    l.type = Light::Type::Directional;
    if (trial < 3) {
      l.vec[trial] = trial == 1 ? -1.0f : 1.0f;  // axis-aligned: exactly zero
    } else {
      r.unit(l.vec);
    }
    for (float& c : l.color) c = 1.0f;
    for (size_t i = 0; i < s.in.n; ++i) {
      const float scale = (i % 2 ? -1.0f : 1.0f) * r.logu(1e-3f, 1e3f);
      for (int c = 0; c < 3; ++c) s.in.tangent(c)[i] = l.vec[c] * scale;
    }
    for_each_target([&](int64_t) {
      Outputs got(s.in.n);
      shade_fur(p, &l, 1, s.eye, s.in.soa(), got.soa());
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < s.in.n; ++i) {
          if (trial < 3) {
            ASSERT_EQ(got.at(c, i), 0.0f) << "trial " << trial << " lane " << i;
          } else {
            ASSERT_LE(got.at(c, i), 1e-6f) << "trial " << trial << " lane " << i;
          }
        }
    });
  }
  // And the same direction, turned a quarter turn, lights fully: the test can fail.
  Light l{};
  l.type = Light::Type::Directional;
  l.vec[0] = 1.0f;
  for (float& c : l.color) c = 1.0f;
  for (size_t i = 0; i < s.in.n; ++i) s.in.set3(&Inputs::tangent, i, 0.0f, 1.0f, 0.0f);
  Outputs got(s.in.n);
  shade_fur(p, &l, 1, s.eye, s.in.soa(), got.soa());
  for (size_t i = 0; i < s.in.n; ++i) {
    const float tex = std::fmin(std::fmax(s.in.texel(0)[i], 0.0f), 1.0f);
    const float h = std::fmin(std::fmax(s.in.height()[i], 0.0f), 1.0f);
    const float ao = h + (1 - h) * p.ambient_occlusion_root;
    EXPECT_NEAR(got.at(0, i), ao * tex, 1e-6f) << "lane " << i;
  }
}

TEST(FurLighting, HeightZeroDarkensByExactlyTheRootFactor) {
  PropertyScene s;
  const std::vector<Light> lights = {
      {Light::Type::Directional, {0.3f, 0.8f, 0.5f}, {1.0f, 0.9f, 0.7f}},
      {Light::Type::Point, {2.0f, -1.0f, 3.0f}, {0.5f, 0.6f, 0.9f}},
      {Light::Type::Ambient, {0, 0, 0}, {0.1f, 0.1f, 0.2f}},
  };
  for (float root : {0.0f, 0.35f, 0.7f, 1.0f}) {
    FurLightParams p;
    p.ambient_occlusion_root = root;
    for_each_target([&](int64_t) {
      Outputs tip(s.in.n), base(s.in.n);
      for (size_t i = 0; i < s.in.n; ++i) s.in.height()[i] = 1.0f;
      shade_fur(p, lights.data(), lights.size(), s.eye, s.in.soa(), tip.soa());
      for (size_t i = 0; i < s.in.n; ++i) s.in.height()[i] = 0.0f;
      shade_fur(p, lights.data(), lights.size(), s.eye, s.in.soa(), base.soa());
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < s.in.n; ++i)
          ASSERT_EQ(base.at(c, i), root * tip.at(c, i)) << "root " << root << " lane " << i << " channel " << c;
    });
  }
}

TEST(FurLighting, OutputScalesLinearlyWithLightColour) {
  PropertyScene s;
  Rng r(0x11fe);
  for (int trial = 0; trial < 8; ++trial) {
    const FurLightParams p = random_params(r);
    const std::vector<Light> lights = random_lights(r);
    for (float k : {2.0f, 3.7f, 0.01f}) {
      std::vector<Light> scaled = lights;
      for (Light& l : scaled)
        for (float& c : l.color) c *= k;
      for_each_target([&](int64_t) {
        Outputs a(s.in.n), b(s.in.n);
        shade_fur(p, lights.data(), lights.size(), s.eye, s.in.soa(), a.soa());
        shade_fur(p, scaled.data(), scaled.size(), s.eye, s.in.soa(), b.soa());
        for (int c = 0; c < 3; ++c)
          for (size_t i = 0; i < s.in.n; ++i) {
            const double want = double(k) * a.at(c, i);
            if (k == 2.0f) {  // scaling by a power of two is exact through every operation
              ASSERT_EQ(b.at(c, i), float(want)) << "trial " << trial << " lane " << i;
            } else {
              ASSERT_NEAR(b.at(c, i), want, 1e-6 * want + 1e-30) << "trial " << trial << " k " << k << " lane " << i;
            }
          }
        for (size_t i = 0; i < s.in.n; ++i) ASSERT_EQ(a.at(3, i), b.at(3, i));
      });
    }
  }
}

// Every lane of `in` one fragment at the origin: tangent along +x, normal +z (unnormalised, as
// interpolation leaves them), at the tip, texel 0.5.
void fill_simple_frame(Inputs& in) {
  for (size_t i = 0; i < in.n; ++i) {
    in.set3(&Inputs::pos, i, 0, 0, 0);
    in.set3(&Inputs::tangent, i, 2, 0, 0);
    in.set3(&Inputs::normal, i, 0, 0, 3);
    in.height()[i] = 1.0f;
    for (int c = 0; c < 4; ++c) in.texel(c)[i] = 0.5f;
  }
}

// Kajiya-Kay by hand for one fragment: tangent along +x, normal +z, light straight above the
// normal (sin(T, L) = 1, N.L = 1) and behind the surface (N.L = -1: the wrap factor alone).
TEST(FurLighting, KnownValuesForASimpleFrame) {
  Inputs in(16);
  fill_simple_frame(in);
  FurLightParams p;
  p.specular = 0.0f;
  p.diffuse = 0.8f;
  p.backlight_wrap = 0.25f;
  const float eye[3] = {0, 0, 4};
  const Light above{Light::Type::Directional, {0, 0, 1}, {1, 1, 1}};
  const Light below{Light::Type::Directional, {0, 0, -1}, {1, 1, 1}};
  for_each_target([&](int64_t) {
    Outputs o(16);
    shade_fur(p, &above, 1, eye, in.soa(), o.soa());
    EXPECT_FLOAT_EQ(o.at(0, 0), 0.5f * 0.8f);
    shade_fur(p, &below, 1, eye, in.soa(), o.soa());
    EXPECT_FLOAT_EQ(o.at(0, 0), 0.5f * 0.8f * 0.25f);
  });
  // Specular alone: eye and light both along +z, so H = +z is perpendicular to T: lobe = 1.
  p.diffuse = 0.0f;
  p.specular = 0.5f;
  for_each_target([&](int64_t) {
    Outputs o(16);
    shade_fur(p, &above, 1, eye, in.soa(), o.soa());
    EXPECT_FLOAT_EQ(o.at(1, 0), 0.5f);
    shade_fur(p, &below, 1, eye, in.soa(), o.soa());
    EXPECT_EQ(o.at(1, 0), 0.0f);  // behind the surface: no specular
  });
}

// The lobe's exponent on the sine is the shininess itself (sin^shininess, evaluated as
// (sin^2)^(shininess/2)). The known values above put H perpendicular to T, where any exponent
// gives 1: here H is 60 degrees from T, sin = sqrt(3)/2, so the lobe is 0.75^(shininess/2).
TEST(FurLighting, SpecularLobeIsTheSineToTheShininess) {
  Inputs in(16);
  const float c30 = std::sqrt(0.75f);
  fill_simple_frame(in);
  // Eye and light along the same direction, 30 degrees from N toward T: H = L, N.L = cos 30.
  const Light l{Light::Type::Directional, {0.5f, 0, c30}, {1, 1, 1}};
  const float eye[3] = {2.0f, 0, 4.0f * c30};
  for (float shininess : {40.0f, 7.0f, 12.5f}) {
    FurLightParams p;
    p.diffuse = 0.0f;
    p.specular = 0.5f;
    p.shininess = shininess;
    const double want = 0.5 * std::pow(0.75, shininess / 2.0) * std::sqrt(0.75);
    Outputs r(16);
    shade_fur_reference(p, &l, 1, eye, in.soa(), r.soa());
    EXPECT_NEAR(r.at(0, 0), want, 1e-6 * want) << "reference, shininess " << shininess;
    for_each_target([&](int64_t) {
      Outputs o(16);
      shade_fur(p, &l, 1, eye, in.soa(), o.soa());
      EXPECT_NEAR(o.at(0, 0), want, 1e-5 * want) << "kernel, shininess " << shininess;
    });
  }
}

TEST(FurLighting, MatchLlvmpipeMatchesReference) {
  Rng r(0x11f3);
  const size_t n = 65536;
  Inputs in(n);
  random_surface(r, in);
  in.set3(&Inputs::normal, 0, 0, 0, 0);
  in.set3(&Inputs::normal, 1, 1e-40f, 0, 0);
  in.set3(&Inputs::normal, 2, 3e38f, -3e38f, 0);
  for (int trial = 0; trial < 4; ++trial) {
    float dir[3];
    r.unit(dir);
    for (float& v : dir) v *= r.uni(0.1f, 10.0f);
    Outputs ref(n);
    shade_fur_match_llvmpipe_reference(dir, in.soa(), ref.soa());
    for_each_target([&](int64_t) {
      Outputs got(n);
      shade_fur_match_llvmpipe(dir, in.soa(), got.soa());
      expect_close(ref, got);
    });
  }
  // The harness's light and a lane facing it: texel x 1.
  const float harness[3] = {0.3f, 0.8f, 0.5f};
  for (size_t i = 0; i < 16; ++i) in.set3(&Inputs::normal, i, 0.3f, 0.8f, 0.5f);
  for (int c = 0; c < 4; ++c) in.texel(c)[0] = 0.5f;
  Outputs got(n);
  shade_fur_match_llvmpipe(harness, in.soa(), got.soa());
  EXPECT_NEAR(got.at(0, 0), 0.5f, 1e-6f);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FurLighting, BadInputsNameTheField) {
  Inputs in(32);
  Outputs out(32);
  const float eye[3] = {0, 0, 5};
  const Light light{Light::Type::Directional, {0, 1, 0}, {1, 1, 1}};
  FurLightParams p;
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, eye, in.soa(), out.soa()); }), "(no error)");

  p.shininess = 0.5f;
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, eye, in.soa(), out.soa()); }).rfind("shininess: must be in", 0), 0u);
  p = FurLightParams{};
  p.backlight_wrap = NAN;
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, eye, in.soa(), out.soa()); }).rfind("backlight_wrap: must be a finite", 0), 0u);
  p = FurLightParams{};
  p.ambient_occlusion_root = 1.5f;
  EXPECT_NE(error_of([&] { shade_fur_reference(p, &light, 1, eye, in.soa(), out.soa()); }).find("ambient_occlusion_root"),
            std::string::npos);
  p = FurLightParams{};

  const float bad_eye[3] = {0, INFINITY, 0};
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, bad_eye, in.soa(), out.soa()); }), "eye[1]: must be finite");
  Light bad_light = light;
  bad_light.color[2] = -1.0f;
  EXPECT_EQ(error_of([&] { shade_fur(p, &bad_light, 1, eye, in.soa(), out.soa()); }).rfind("lights[0].color[2]", 0), 0u);

  FurSurfaceSoA s = in.soa();
  s.n = 20;
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, eye, s, out.soa()); }), "n: must be a multiple of 16, got 20");
  s = in.soa();
  s.tangent[1] = in.tangent(1) + 1;
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, eye, s, out.soa()); }), "tangent[y]: must be 64-byte aligned");
  s = in.soa();
  s.height = nullptr;
  EXPECT_EQ(error_of([&] { shade_fur(p, &light, 1, eye, s, out.soa()); }), "height: must not be null");
  // The llvmpipe lighting does not read height, tangent or pos.
  s.tangent[0] = nullptr;
  s.pos[2] = nullptr;
  const float dir[3] = {0, 1, 0};
  EXPECT_EQ(error_of([&] { shade_fur_match_llvmpipe(dir, s, out.soa()); }), "(no error)");
  FurOutSoA o = out.soa();
  o.rgba[3] = nullptr;
  EXPECT_EQ(error_of([&] { shade_fur_match_llvmpipe(dir, in.soa(), o); }), "rgba[3]: must not be null");
  const float zero_dir[3] = {0, 0, 0};
  EXPECT_EQ(error_of([&] { shade_fur_match_llvmpipe(zero_dir, in.soa(), out.soa()); }),
            "light_dir: must be a non-zero direction");
  const float nan_dir[3] = {0, NAN, 0};
  EXPECT_EQ(error_of([&] { shade_fur_match_llvmpipe_reference(nan_dir, in.soa(), out.soa()); }).rfind("light_dir[1]", 0),
            0u);
}

// More lights than the kernel keeps on the stack: the same result as the reference.
TEST(FurLighting, ManyLights) {
  Rng r(0x3a3);
  Inputs in(256);
  random_surface(r, in);
  std::vector<Light> lights;
  for (int k = 0; k < 40; ++k) {
    const std::vector<Light> more = random_lights(r);
    lights.insert(lights.end(), more.begin(), more.end());
  }
  const float eye[3] = {3, -2, 4};
  Outputs ref(in.n);
  shade_fur_reference(FurLightParams{}, lights.data(), lights.size(), eye, in.soa(), ref.soa());
  for_each_target([&](int64_t) {
    Outputs got(in.n);
    shade_fur(FurLightParams{}, lights.data(), lights.size(), eye, in.soa(), got.soa());
    expect_close(ref, got);
  });
}

}  // namespace fur_lighting_test
}  // namespace pelt::shading
