// Skin shading throughput: lanes (visible pixels) per second per Highway target, for the layered
// skin kernel with the default SkinParams (the configuration `pelt bench skin` renders), for the
// Normal Blur SSS epidermis (which also reads three blurred normals per lane), for the Lambert
// kernel as the yardstick the skin frame is compared with, and for the double-precision
// reference once (it does not dispatch). One batch is a 64x64 tile's worth of pixels, as the
// renderer calls it; the lighting is the skin benchmark's: a key and a fill directional light and
// an ambient term. Normals are random unit vectors turned toward the viewer and positions lie in
// front of the eye, so the lanes' work is representative of a head seen from the front (some
// lanes unlit by one light, grazing angles present). The normal map kernel that runs before a
// normal-mapped material's shading is timed on the same batch size: interpolated tangent frames
// (unit normals, tangents skewed and shortened by interpolation as on a mesh, both handednesses)
// and 8-bit texels around the flat (0.5, 0.5, 1), with its double reference once.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include "shading/normal_map.h"
#include "shading/skin_kernels.h"
#include "tools/bench/kernel_loop.h"

namespace {

using namespace pelt::shading;

constexpr size_t kLanes = 64 * 64;
constexpr float kEye[3] = {0.0f, 0.0f, 30.0f};

// A random unit vector (normal distribution per component, so every direction alike).
void random_unit(std::mt19937& gen, float v[3]) {
  std::normal_distribution<float> nd;
  float l2 = 0.0f;
  do {
    l2 = 0.0f;
    for (int c = 0; c < 3; ++c) {
      v[c] = nd(gen);
      l2 += v[c] * v[c];
    }
  } while (l2 < 1e-6f);
  for (int c = 0; c < 3; ++c) v[c] /= std::sqrt(l2);
}

struct Batch {
  // pos, normal, albedo (3 each), blurred normals (9), then rgb, alpha and the three layers (13).
  pelt::bench::AlignedArrays arrays{31, kLanes};
  Batch() {
    std::mt19937 gen(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (size_t i = 0; i < kLanes; ++i) {
      // A point of a head-sized object around the origin, seen from kEye.
      const float p[3] = {4.0f * u(gen), 4.5f * u(gen), 3.0f * u(gen)};
      float n[3];
      random_unit(gen, n);
      float nv = 0.0f;
      for (int c = 0; c < 3; ++c) nv += n[c] * (kEye[c] - p[c]);
      if (nv < 0.0f)
        for (float& c : n) c = -c;
      for (int c = 0; c < 3; ++c) {
        arrays[c][i] = p[c];
        arrays[3 + c][i] = n[c];
        arrays[6 + c][i] = 0.5f + 0.5f * u(gen);
        for (int ch = 0; ch < 3; ++ch) arrays[9 + 3 * ch + c][i] = n[c] + 0.2f * u(gen);
      }
    }
  }
  SurfaceSoA surface() const {
    SurfaceSoA s{};
    s.n = kLanes;
    for (int c = 0; c < 3; ++c) {
      s.pos[c] = arrays[c];
      s.normal[c] = arrays[3 + c];
      s.albedo[c] = arrays[6 + c];
      for (int a = 0; a < 3; ++a) s.blurred_normal[c][a] = arrays[9 + 3 * c + a];
    }
    return s;
  }
  // The renderer asks for rgb and alpha only unless a single layer is displayed.
  ShadeOutSoA out() const {
    ShadeOutSoA o{};
    for (int c = 0; c < 3; ++c) o.rgb[c] = arrays[18 + c];
    o.alpha = arrays[21];
    return o;
  }
};

std::vector<Light> bench_lights() {
  auto unit = [](float x, float y, float z) {
    const float len = std::sqrt(x * x + y * y + z * z);
    return std::vector<float>{x / len, y / len, z / len};
  };
  const std::vector<float> key = unit(-0.5f, 0.6f, 0.8f), fill = unit(0.7f, 0.1f, 0.6f);
  return {{Light::Type::Directional, {key[0], key[1], key[2]}, {1.0f, 1.0f, 1.0f}},
          {Light::Type::Directional, {fill[0], fill[1], fill[2]}, {0.35f, 0.35f, 0.35f}},
          {Light::Type::Ambient, {0.0f, 0.0f, 0.0f}, {0.1f, 0.1f, 0.1f}}};
}

enum class Kernel { skin, skin_reference, lambert };

void BM_Skin(benchmark::State& state, int64_t target, Kernel kernel, MultipleScattering ms) {
  const Batch b;
  const SurfaceSoA s = b.surface();
  const ShadeOutSoA o = b.out();
  SkinParams p;
  p.multiple_scattering = ms;
  const std::vector<Light> lights = bench_lights();
  pelt::bench::time_lanes(state, target, kLanes, [&] {
    switch (kernel) {
      case Kernel::skin:
        shade_skin(p, lights.data(), lights.size(), kEye, s, o);
        break;
      case Kernel::skin_reference:
        shade_skin_reference(p, lights.data(), lights.size(), kEye, s, o);
        break;
      case Kernel::lambert:
        shade_lambert(lights.data(), lights.size(), kEye, s, o);
        break;
    }
  });
}

// normal (3), tangent (4), texel (3), then the perturbed normal (3).
struct NormalMapBatch {
  pelt::bench::AlignedArrays arrays{13, kLanes};
  NormalMapBatch() {
    std::mt19937 gen(12);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (size_t i = 0; i < kLanes; ++i) {
      float n[3], r[3];
      random_unit(gen, n);
      random_unit(gen, r);
      // A tangent orthogonal to n, then skewed and shortened up to 10% (interpolation).
      const float rn = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
      float t[3], tl2 = 0.0f;
      for (int c = 0; c < 3; ++c) {
        t[c] = r[c] - rn * n[c];
        tl2 += t[c] * t[c];
      }
      const float scale = (0.9f + 0.1f * u(gen)) / std::sqrt(tl2);
      for (int c = 0; c < 3; ++c) {
        arrays[c][i] = n[c];
        arrays[3 + c][i] = t[c] * scale + 0.1f * u(gen) * n[c];
      }
      arrays[6][i] = u(gen) < 0.0f ? -1.0f : 1.0f;
      arrays[7][i] = std::round(127.5f + 40.0f * u(gen)) / 255.0f;
      arrays[8][i] = std::round(127.5f + 40.0f * u(gen)) / 255.0f;
      arrays[9][i] = std::round(235.0f + 20.0f * u(gen)) / 255.0f;
    }
  }
  NormalMapSoA in() const {
    return NormalMapSoA{kLanes,
                        {arrays[0], arrays[1], arrays[2]},
                        {arrays[3], arrays[4], arrays[5], arrays[6]},
                        {arrays[7], arrays[8], arrays[9]}};
  }
};

void BM_NormalMap(benchmark::State& state, int64_t target, bool reference) {
  const NormalMapBatch b;
  const NormalMapSoA in = b.in();
  float* const out[3] = {b.arrays[10], b.arrays[11], b.arrays[12]};
  pelt::bench::time_lanes(state, target, kLanes, [&] {
    (reference ? perturb_normals_reference : perturb_normals)(in, out);
  });
}

int RegisterAll() {
  struct Case {
    const char* name;
    Kernel kernel;
    MultipleScattering ms;
  };
  const Case cases[] = {
      {"skin/default", Kernel::skin, MultipleScattering::paper},
      {"skin/normal_blur", Kernel::skin, MultipleScattering::normal_blur},
      {"lambert", Kernel::lambert, MultipleScattering::paper},
  };
  for (int64_t target : hwy::SupportedAndGeneratedTargets())
    for (const Case& c : cases) {
      const std::string name = std::string("SkinKernels/") + c.name + "/" + hwy::TargetName(target);
      benchmark::RegisterBenchmark(name.c_str(), BM_Skin, target, c.kernel, c.ms)->Unit(benchmark::kMicrosecond);
    }
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    const std::string name = std::string("SkinKernels/normal_map/") + hwy::TargetName(target);
    benchmark::RegisterBenchmark(name.c_str(), BM_NormalMap, target, false)->Unit(benchmark::kMicrosecond);
  }
  // Scalar double precision: the same for every target, so measured once.
  benchmark::RegisterBenchmark("SkinKernels/skin_reference/default", BM_Skin, int64_t{0}, Kernel::skin_reference,
                               MultipleScattering::paper)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("SkinKernels/normal_map_reference", BM_NormalMap, int64_t{0}, true)
      ->Unit(benchmark::kMicrosecond);
  return 0;
}
const int kRegistered = RegisterAll();

}  // namespace

BENCHMARK_MAIN();
