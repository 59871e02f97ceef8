// Random inputs shared by the shading kernels' random tests: a seeded generator and random
// light sets (1-4 lights of any type, directional vectors of random length, colours to 2).
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "shading/light.h"

namespace pelt::shading::testing {

struct Rng {
  std::mt19937_64 gen;
  explicit Rng(uint64_t seed) : gen(seed) {}
  float uni(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(gen); }
  float logu(float lo, float hi) { return std::exp(uni(std::log(lo), std::log(hi))); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(gen); }
  void unit(float v[3]) {
    std::normal_distribution<float> nd;
    float l2 = 0;
    do {
      for (int c = 0; c < 3; ++c) v[c] = nd(gen);
      l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (l2 < 1e-6f);
    for (int c = 0; c < 3; ++c) v[c] /= std::sqrt(l2);
  }
};

inline std::vector<Light> random_lights(Rng& r) {
  std::vector<Light> lights(1 + r.pick(4));
  for (Light& l : lights) {
    l.type = static_cast<Light::Type>(r.pick(3));
    if (l.type == Light::Type::Directional) {
      r.unit(l.vec);
      const float len = r.uni(0.5f, 2.0f);
      for (float& v : l.vec) v *= len;
    } else {
      for (float& v : l.vec) v = r.uni(-3, 3);
    }
    for (float& c : l.color) c = r.uni(0, 2);
  }
  return lights;
}

// An eye in a random direction, 2 to 10 from the origin (the random surfaces lie within 1 of it).
inline void random_eye(Rng& r, float eye[3]) {
  r.unit(eye);
  const float dist = r.uni(2, 10);
  for (int c = 0; c < 3; ++c) eye[c] *= dist;
}

}  // namespace pelt::shading::testing
