// Texture sampling throughput: samples per second per filter, Highway target, texture size
// and layout (RGBA8 linear or sRGB, luminance-alpha), at 1 and 4 texels per pixel
// (magnified-to-1:1 and minified, the range of the fur shells). Each iteration samples 64K lanes laid out as the 4x4 blocks of a rotated,
// slightly perspective screen-space mapping, as a FragmentBatch delivers them; SampleMasked adds a
// fur batch's partly covered blocks. BlockLods times the mipmapped filters' first pass alone, the
// level of detail of each 4x4 block (raster::block_lods), per block.
#include <benchmark/benchmark.h>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <hwy/aligned_allocator.h>
#include <hwy/targets.h>

#include "raster/texture.h"

namespace {

using namespace pelt::raster;

constexpr size_t kLanes = 64 * 1024;

// The stored layouts measured: RGBA8 (linear or sRGB colour) and luminance-alpha (La8, the
// fur shells').
enum class Kind { rgba8, srgb, la8 };

Texture make(int size, Kind kind) {
  std::mt19937 rng(static_cast<uint32_t>(size));
  std::vector<uint8_t> bytes(size_t(size) * size_t(size) * 4);
  for (auto& b : bytes) b = uint8_t(rng());
  Texture t;
  if (kind == Kind::la8 ? Texture::from_la8(size, size, bytes.data(), t)
                        : Texture::from_rgba8(size, size, bytes.data(),
                                              kind == Kind::srgb ? TexelEncoding::Srgb : TexelEncoding::Linear, t))
    std::abort();
  return t;
}

const Texture& texture(int size, Kind kind) {
  static const Texture t256 = make(256, Kind::rgba8), t1024 = make(1024, Kind::rgba8), s256 = make(256, Kind::srgb),
                       l256 = make(256, Kind::la8);
  if (kind == Kind::srgb) return s256;
  if (kind == Kind::la8) return l256;
  return size == 256 ? t256 : t1024;
}

// Blocks of a 256-block-wide screen region, `texels_per_pixel` texels of a size^2 texture
// per pixel, rotated by 30 degrees, with a mild perspective bend.
void coords(int size, float texels_per_pixel, std::vector<float>& u, std::vector<float>& v) {
  u.resize(kLanes);
  v.resize(kLanes);
  const float s = texels_per_pixel / float(size), c = std::cos(0.52f), n = std::sin(0.52f);
  for (size_t b = 0; b < kLanes / 16; ++b) {
    const float bx = float(b % 256) * 4.0f, by = float(b / 256) * 4.0f;
    for (int l = 0; l < 16; ++l) {
      const float x = bx + float(l % 4), y = by + float(l / 4);
      const float w = 1.0f + 0.0002f * (x + y);
      u[b * 16 + size_t(l)] = (c * x - n * y) * s / w + 0.3f;
      v[b * 16 + size_t(l)] = (n * x + c * y) * s / w + 0.7f;
    }
  }
}

// Block masks like a fur batch's: 40 % of the blocks whole, the others cut by a random straight
// edge (a triangle's side) keeping 1 to 15 lanes; about 70 % of the lanes in all, as on the furry
// box. Through the sampler's dense lanes on 16-lane targets (raster/texture_kernels.cc).
std::vector<uint16_t> fur_like_masks(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f), offset(-1.2f, 1.2f), unit(0.0f, 1.0f);
  std::vector<uint16_t> masks(kLanes / 16);
  for (uint16_t& m : masks) {
    if (unit(rng) < 0.4f) {
      m = 0xFFFF;
      continue;
    }
    do {
      const float a = angle(rng), c = offset(rng);
      m = 0;
      for (int l = 0; l < 16; ++l)
        if (std::cos(a) * (float(l % 4) - 1.5f) + std::sin(a) * (float(l / 4) - 1.5f) < c * 2.0f) m |= uint16_t(1u << l);
    } while (m == 0 || m == 0xFFFF);
  }
  return masks;
}

// `masked`: with fur_like_masks, counting the wanted lanes as the items.
void BM_Sample(benchmark::State& state, int64_t target, Filter filter, int size, Kind kind,
               float texels_per_pixel, bool masked, Wrap wrap) {
  hwy::SetSupportedTargetsForTest(target);
  const Texture& tex = texture(size, kind);
  std::vector<float> u, v;
  coords(size, texels_per_pixel, u, v);
  const std::vector<uint16_t> masks = masked ? fur_like_masks(7) : std::vector<uint16_t>{};
  int64_t items = masked ? 0 : int64_t(kLanes);
  for (uint16_t m : masks) items += std::popcount(unsigned{m});
  auto o0 = hwy::AllocateAligned<float>(kLanes), o1 = hwy::AllocateAligned<float>(kLanes),
       o2 = hwy::AllocateAligned<float>(kLanes), o3 = hwy::AllocateAligned<float>(kLanes);
  float* const out[4] = {o0.get(), o1.get(), o2.get(), o3.get()};
  const SamplerState s{filter, wrap, wrap, 0.0f};
  for (auto _ : state) {
    sample(tex, s, u.data(), v.data(), kLanes, out, masked ? masks.data() : nullptr);
    benchmark::DoNotOptimize(o3[kLanes - 1]);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * items);
  state.counters["texture_KiB"] = double(tex.bytes()) / 1024.0;
  if (masked) state.counters["wanted_lanes_%"] = 100.0 * double(items) / double(kLanes);
  hwy::SetSupportedTargetsForTest(0);
}

// Wrap::Mirror's fold of the coordinates of coords(256, 4) (both axes' worth: u, then v), by the
// kernel sample() calls or by its scalar reference, lane by lane (what sample() ran until
// 2026-11-28).
void BM_FoldMirror(benchmark::State& state, int64_t target, bool reference) {
  hwy::SetSupportedTargetsForTest(target);
  std::vector<float> u, v, out(kLanes);
  coords(256, 4.0f, u, v);
  for (auto _ : state) {
    for (const std::vector<float>* c : {&u, &v}) {
      if (reference)
        for (size_t i = 0; i < kLanes; ++i) out[i] = fold_mirror_reference((*c)[i]);
      else
        fold_mirror(c->data(), out.data(), kLanes);
      benchmark::DoNotOptimize(out[kLanes - 1]);
      benchmark::ClobberMemory();
    }
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(2 * kLanes));
  hwy::SetSupportedTargetsForTest(0);
}

// The level of detail of the 4096 blocks of coords(256, 4): the pass the trilinear sampler runs
// over every chunk of blocks before its taps.
void BM_BlockLods(benchmark::State& state, int64_t target) {
  hwy::SetSupportedTargetsForTest(target);
  std::vector<float> u, v;
  coords(256, 4.0f, u, v);
  const size_t blocks = kLanes / 16;
  std::vector<double> lods(blocks);
  for (auto _ : state) {
    block_lods(u.data(), v.data(), blocks, 256, 256, 0.0f, 9, lods.data());
    benchmark::DoNotOptimize(lods[blocks - 1]);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(blocks));
  hwy::SetSupportedTargetsForTest(0);
}

const char* filter_name(Filter f) {
  switch (f) {
    case Filter::Nearest: return "nearest";
    case Filter::Bilinear: return "bilinear";
    case Filter::BilinearMip: return "bilinear_mip";
    case Filter::Trilinear: break;
  }
  return "trilinear";
}

void register_all() {
  for (int64_t target : hwy::SupportedAndGeneratedTargets())
    for (Filter f : {Filter::Nearest, Filter::Bilinear, Filter::BilinearMip, Filter::Trilinear})
      for (auto [size, kind] : {std::pair{256, Kind::rgba8}, std::pair{1024, Kind::rgba8}, std::pair{256, Kind::srgb},
                                std::pair{256, Kind::la8}})
        for (float tpp : {1.0f, 4.0f}) {
          const char* suffix = kind == Kind::srgb ? "_srgb" : kind == Kind::la8 ? "_la8" : "_rgba8";
          const std::string name = std::string("Sample/") + hwy::TargetName(target) + "/" + filter_name(f) +
                                   "/" + std::to_string(size) + suffix + "/texels_per_pixel:" + std::to_string(int(tpp));
          benchmark::RegisterBenchmark(name.c_str(), BM_Sample, target, f, size, kind, tpp, false, Wrap::Repeat);
        }
  for (int64_t target : hwy::SupportedAndGeneratedTargets())
    for (Filter f : {Filter::Bilinear, Filter::Trilinear})
      for (Kind kind : {Kind::rgba8, Kind::la8}) {
        const std::string name = std::string("SampleMasked/") + hwy::TargetName(target) + "/" + filter_name(f) +
                                 (kind == Kind::la8 ? "/256_la8" : "/256_rgba8") + "/texels_per_pixel:4";
        benchmark::RegisterBenchmark(name.c_str(), BM_Sample, target, f, 256, kind, 4.0f, true, Wrap::Repeat);
      }
  // A mirrored map (glTF's 33648), folded before the clamp's path: against Sample/.../trilinear/256_srgb.
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    const std::string name =
        std::string("SampleMirror/") + hwy::TargetName(target) + "/trilinear/256_srgb/texels_per_pixel:4";
    benchmark::RegisterBenchmark(name.c_str(), BM_Sample, target, Filter::Trilinear, 256, Kind::srgb, 4.0f, false,
                                 Wrap::Mirror);
    benchmark::RegisterBenchmark((std::string("FoldMirror/") + hwy::TargetName(target)).c_str(), BM_FoldMirror, target,
                                 false);
  }
  benchmark::RegisterBenchmark("FoldMirror/reference", BM_FoldMirror, int64_t{0}, true);
  for (int64_t target : hwy::SupportedAndGeneratedTargets())
    benchmark::RegisterBenchmark((std::string("BlockLods/") + hwy::TargetName(target)).c_str(), BM_BlockLods, target);
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
