// Rasterizer throughput: triangles and pixels per second by triangle area, opaque
// (depth-tested, visibility + shading) and blended (src-over), per Highway target and
// thread count. The triangles tile a 1024x768 screen exactly, so pixels per frame are
// known: every pixel is covered once per layer.
//
// Raster/dense_head: the rasterizer alone on `pelt bench skin`'s Female body (the head scan
// refined and decimated to 120,518 triangles of about 3.5 visible pixels each), framed as
// that bench frames it and carrying the skin draw's six varyings, with a shader that
// writes a constant: the front end and tile costs of that table's row without its lighting.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <hwy/targets.h>

#include "raster/renderer.h"
#include "tools/bench/skin_meshes.h"

namespace {

using namespace pelt::raster;

class FlatShader final : public Shader {
 public:
  explicit FlatShader(bool derivatives = true) : derivatives_(derivatives) {}
  bool uses_derivatives() const override { return derivatives_; }
  void shade(const FragmentBatch& b) const override {
    const size_t lanes = size_t{b.blocks} * kBlockLanes;
    for (size_t i = 0; i < lanes; ++i) {
      b.out[0][i] = 0.8f;
      b.out[1][i] = 0.5f;
      b.out[2][i] = 0.2f;
      b.out[3][i] = 0.5f;
    }
  }

 private:
  bool derivatives_;
};

constexpr int kW = 1024, kH = 768;

struct Tiling {
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> idx;
};

// Right triangles of `area` pixels (two per square cell) covering the screen, `layers`
// copies at decreasing depth (front-most last, so every layer passes a Less test).
Tiling tile_screen(double area, int layers) {
  Tiling t;
  const double side = std::sqrt(2.0 * area);
  const int nx = int(std::ceil(kW / side)), ny = int(std::ceil(kH / side));
  for (int l = 0; l < layers; ++l) {
    const float z = 0.5f - 0.1f * l;
    const uint32_t base = uint32_t(t.pos.size());
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        t.pos.push_back({float(i * side / kW * 2.0 - 1.0), float(1.0 - j * side / kH * 2.0), z});
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const uint32_t a = base + j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
        t.idx.insert(t.idx.end(), {a, c, d, a, d, b});
      }
  }
  return t;
}

void BM_Raster(benchmark::State& state, int64_t target, bool blended) {
  const double area = double(state.range(0));
  const int threads = int(state.range(1));
  hwy::SetSupportedTargetsForTest(target);
  // Enough triangles that per-frame costs (clear, resolve) do not hide per-triangle ones.
  const int layers = area >= 1000 ? 8 : area >= 100 ? 8 : 1;
  const Tiling t = tile_screen(area, layers);
  const FlatShader shader;
  DrawCall d;
  d.positions = t.pos.data();
  d.vertex_count = uint32_t(t.pos.size());
  d.indices = t.idx.data();
  d.triangle_count = uint32_t(t.idx.size() / 3);
  d.shader = &shader;
  if (blended) {
    d.state.blend = BlendMode::AlphaOver;
    d.state.depth_write = false;
  }
  std::vector<float> color(size_t(kW) * kH * 4), depth(size_t(kW) * kH);
  Renderer r(threads);
  const RenderTarget rt{kW, kH, color.data(), depth.data(), nullptr};
  RasterStats st;
  for (auto _ : state) {
    r.render({&d, 1}, RenderOptions{}, rt, &st);
    benchmark::DoNotOptimize(color.data());
  }
  const double frames = double(state.iterations());
  state.counters["tris/s"] = benchmark::Counter(frames * d.triangle_count, benchmark::Counter::kIsRate);
  state.counters["px/s"] = benchmark::Counter(
      frames * double(blended ? st.fragments_blended : st.fragments_visible), benchmark::Counter::kIsRate);
  state.counters["front_ms"] = st.ms_front;
  hwy::SetSupportedTargetsForTest(0);
}

// The Female body row of `pelt bench skin`, built once (subdivision and decimation take a
// few seconds), with positions and normals interleaved as the skin draw's varyings.
struct DenseMesh {
  pelt::Mesh mesh;
  std::vector<float> varyings;
  glm::mat4 clip_from_object{1.0f};
};

const DenseMesh& dense_head() {
  static const DenseMesh m = [] {
    DenseMesh d;
    d.mesh = pelt::bench::make_skin_bench_meshes(pelt::bench::find_head_scan("raster_bench"))[2].mesh;
    for (size_t v = 0; v < d.mesh.vertex_count(); ++v)
      for (const glm::vec3& a : {d.mesh.positions[v], d.mesh.normals[v]}) d.varyings.insert(d.varyings.end(), {a.x, a.y, a.z});
    const pelt::bench::SkinBenchView view = pelt::bench::skin_bench_view(d.mesh, kW, kH);
    const glm::mat4 proj =
        glm::perspective(glm::radians(view.fovy_deg), float(kW) / kH, view.near, view.far);
    const glm::mat4 look = glm::lookAt(glm::vec3(0, 0, view.distance), glm::vec3(0), glm::vec3(0, 1, 0));
    d.clip_from_object = proj * look * glm::translate(glm::mat4(1.0f), -view.centre);
    return d;
  }();
  return m;
}

void BM_DenseHead(benchmark::State& state, int64_t target) {
  const int threads = int(state.range(0));
  const DenseMesh* mesh = nullptr;
  try {
    mesh = &dense_head();
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());  // run from inside the checkout or set PELT_SOURCE_DIR
    return;
  }
  const DenseMesh& m = *mesh;
  hwy::SetSupportedTargetsForTest(target);
  const FlatShader shader(false);
  DrawCall d;
  d.positions = m.mesh.positions.data();
  d.vertex_count = uint32_t(m.mesh.vertex_count());
  d.indices = m.mesh.indices.data();
  d.triangle_count = uint32_t(m.mesh.triangle_count());
  d.varyings = m.varyings.data();
  d.varying_count = 6;
  d.clip_from_object = m.clip_from_object;
  d.state.cull = CullMode::Back;
  d.shader = &shader;
  std::vector<float> color(size_t(kW) * kH * 4);
  Renderer r(threads);
  const RenderTarget rt{kW, kH, color.data(), nullptr, nullptr};
  RasterStats st, sum;
  for (auto _ : state) {
    r.render({&d, 1}, RenderOptions{}, rt, &st);
    sum += st;
    benchmark::DoNotOptimize(color.data());
  }
  const double frames = double(state.iterations());
  state.counters["front_ms"] = sum.ms_front / frames;
  state.counters["tiles_ms"] = sum.ms_tiles / frames;
  state.counters["setup"] = double(st.triangles_setup);
  state.counters["pixels"] = double(st.pixels_shaded);
  hwy::SetSupportedTargetsForTest(0);
}

int RegisterAll() {
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    for (bool blended : {false, true}) {
      const std::string name = std::string("Raster/") + (blended ? "blended/" : "opaque/") +
                               hwy::TargetName(target);
      benchmark::RegisterBenchmark(name.c_str(), BM_Raster, target, blended)
          ->ArgNames({"area_px", "threads"})
          ->ArgsProduct({{1, 10, 100, 10000}, {1, 2}})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    benchmark::RegisterBenchmark((std::string("Raster/dense_head/") + hwy::TargetName(target)).c_str(), BM_DenseHead,
                                 target)
        ->ArgNames({"threads"})
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return 0;
}
const int kRegistered = RegisterAll();

}  // namespace

BENCHMARK_MAIN();
