// Fur lighting throughput: lanes (fur fragments) per second per Highway target, for the Kajiya-Kay
// kernel (one directional light; directional + point + ambient; integer and non-integer
// shininess, which take the repeated-squaring and the exp/log lobe; a light straight behind the
// fur, the worst case of the double-precision path for backlit lanes) and for the llvmpipe
// harness's fixed lighting. One batch is a 64x64 tile's worth of fragments, as the renderer calls
// it; the inputs are random, so the lanes' work is representative of fur seen at all angles.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>

#include "shading/fur_lighting.h"
#include "tools/bench/kernel_loop.h"

namespace {

using namespace pelt::shading;

constexpr size_t kLanes = 64 * 64;

struct Batch {
  pelt::bench::AlignedArrays arrays{18, kLanes};  // 14 inputs then 4 outputs
  Batch() {
    std::mt19937 gen(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (size_t k = 0; k < 18; ++k)
      for (size_t i = 0; i < kLanes; ++i) arrays[k][i] = (k == 9 || k >= 10) ? 0.5f + 0.5f * u(gen) : u(gen);
  }
  FurSurfaceSoA surface() const {
    FurSurfaceSoA s{};
    s.n = kLanes;
    for (int c = 0; c < 3; ++c) {
      s.pos[c] = arrays[c];
      s.tangent[c] = arrays[3 + c];
      s.normal[c] = arrays[6 + c];
    }
    s.height = arrays[9];
    for (int c = 0; c < 4; ++c) s.texel[c] = arrays[10 + c];
    return s;
  }
  FurOutSoA out() const { return FurOutSoA{{arrays[14], arrays[15], arrays[16], arrays[17]}}; }
};

enum class Lighting { one_directional, three_lights, backlit, llvmpipe };

void BM_FurLighting(benchmark::State& state, int64_t target, Lighting lighting, float shininess) {
  const Batch b;
  const FurSurfaceSoA s = b.surface();
  const FurOutSoA o = b.out();
  FurLightParams p;
  p.shininess = shininess;
  const float eye[3] = {0.5f, 1.0f, 6.0f};
  std::vector<Light> lights = {{Light::Type::Directional, {0.3f, 0.8f, 0.5f}, {1.0f, 0.95f, 0.9f}}};
  if (lighting == Lighting::backlit) lights[0].vec[2] = -6.0f;  // behind the fur: |L + V| < 0.2 for most lanes
  if (lighting == Lighting::three_lights) {
    lights.push_back({Light::Type::Point, {2.0f, 3.0f, 1.0f}, {0.4f, 0.4f, 0.5f}});
    lights.push_back({Light::Type::Ambient, {0, 0, 0}, {0.1f, 0.1f, 0.12f}});
  }
  const float dir[3] = {0.3f, 0.8f, 0.5f};
  pelt::bench::time_lanes(state, target, kLanes, [&] {
    if (lighting == Lighting::llvmpipe)
      shade_fur_match_llvmpipe(dir, s, o);
    else
      shade_fur(p, lights.data(), lights.size(), eye, s, o);
  });
}

int RegisterAll() {
  struct Case {
    const char* name;
    Lighting lighting;
    float shininess;
  };
  const Case cases[] = {
      {"kajiya_kay/1_directional/shininess_40", Lighting::one_directional, 40.0f},
      {"kajiya_kay/1_directional/shininess_40.5", Lighting::one_directional, 40.5f},
      {"kajiya_kay/1_directional/shininess_512", Lighting::one_directional, 512.0f},
      {"kajiya_kay/dir_point_ambient/shininess_40", Lighting::three_lights, 40.0f},
      {"kajiya_kay/backlit_worst_case/shininess_40", Lighting::backlit, 40.0f},
      {"match_llvmpipe", Lighting::llvmpipe, 40.0f},
  };
  for (int64_t target : hwy::SupportedAndGeneratedTargets())
    for (const Case& c : cases) {
      const std::string name = std::string("FurLighting/") + c.name + "/" + hwy::TargetName(target);
      benchmark::RegisterBenchmark(name.c_str(), BM_FurLighting, target, c.lighting, c.shininess)
          ->Unit(benchmark::kMicrosecond);
    }
  return 0;
}
const int kRegistered = RegisterAll();

}  // namespace

BENCHMARK_MAIN();
