#include "raster/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "raster/clip.h"
#include "raster/frame.h"
#include "raster/parallel.h"
#include "raster/vertex_kernels.h"

namespace pelt::raster {
namespace {

constexpr uint32_t kVertexChunk = 4096;

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

struct Renderer::Impl {
  explicit Impl(int threads) : pool(threads) {}

  ThreadPool pool;
  // Per draw, per vertex: the record set-up and binning read (vertex_kernels.h), and the clip
  // position, read only by clipping.
  struct DrawVertices {
    std::vector<glm::vec4> clip;
    std::vector<FrontVertex> front;
  };
  std::vector<DrawVertices> clip;
  std::vector<BinChunk> chunks;
  std::vector<std::unique_ptr<TileScratch>> scratch;  // per worker slot
  std::vector<uint32_t> tile_order;
  std::vector<uint32_t> tile_load;  // bin items per tile

  struct VertexJob {
    uint32_t draw, first, count;
  };
  std::vector<VertexJob> vertex_jobs;

  void transform(std::span<const DrawCall> draws, const Viewport& vp);
  void front_end(std::span<const DrawCall> draws, const Viewport& vp, int tiles_x, int tiles_y);
  void bin_chunk(BinChunk& ch, const DrawCall& draw, const DrawVertices& dv,
                 const Viewport& vp, const ClipBounds& bounds, int tiles_x, int tiles_y);
};

Renderer::Renderer(int threads) : impl_(std::make_unique<Impl>(threads)) {}
Renderer::~Renderer() = default;
int Renderer::threads() const { return impl_->pool.threads(); }
void Renderer::parallel_for(size_t count, ItemFn fn) { impl_->pool.parallel_for(count, fn); }
size_t Renderer::worker_scratch_bytes() { return sizeof(TileScratch); }

size_t Renderer::exact_sort_bytes(uint32_t cap) {
  // The fragments and their copy grouped by pixel (CompositeExact), each reserved to the count.
  return size_t{cap} * 2 * sizeof(TileScratch::Fragment);
}

void Renderer::Impl::transform(std::span<const DrawCall> draws, const Viewport& vp) {
  if (clip.size() < draws.size()) clip.resize(draws.size());
  vertex_jobs.clear();
  for (uint32_t d = 0; d < draws.size(); ++d) {
    clip[d].clip.resize(draws[d].vertex_count);
    clip[d].front.resize(draws[d].vertex_count);
    for (uint32_t v = 0; v < draws[d].vertex_count; v += kVertexChunk)
      vertex_jobs.push_back({d, v, std::min(kVertexChunk, draws[d].vertex_count - v)});
  }
  const ClipBounds bounds = make_clip_bounds(vp.width, vp.height);
  pool.parallel_for(vertex_jobs.size(), [&](size_t j, int) {
    const VertexJob& job = vertex_jobs[j];
    const DrawCall& draw = draws[job.draw];
    DrawVertices& dv = clip[job.draw];
    // Snaps every vertex that needs no clipping once here, for all triangles that share it.
    transform_vertices(draw.clip_from_object, draw.positions, job.first, job.count, vp, bounds,
                       dv.clip.data(), dv.front.data());
  });
}

// The tile sort's key for the run of triangles [first, first + n) (DrawCall::sort_group): the
// mean view depth of the run (a grid mesh's quad, a fur fin's strip), or NaN when the run does
// not qualify and each triangle keeps its own key. Together, a run sorts as one primitive, its
// triangles one right after the other, so the tiles pack their lanes into shared blocks;
// apart, other layers' triangles of nearly equal depth fall between them. The key is computed
// once per run and chunk, from the run's first triangle on, so every triangle of a run gets
// the same float.
static float run_key(const DrawCall& draw, const FrontVertex* front, uint32_t first, uint32_t n) {
  if (n < 2) return std::numeric_limits<float>::quiet_NaN();
  float sum = 0.0f;
  for (uint32_t q = first; q < first + n; ++q) {
    const uint32_t* t = draw.indices + 3 * size_t{q};
    for (int i = 0; i < 3; ++i)
      if (t[i] >= draw.vertex_count || (front[t[i]].code & kNonFinite)) return std::numeric_limits<float>::quiet_NaN();
    if (q > first && !triangles_share_edge(t - 3, t)) return std::numeric_limits<float>::quiet_NaN();
    sum += front[t[0]].w + front[t[1]].w + front[t[2]].w;
  }
  return sum * (1.0f / float(3 * n));
}

void Renderer::Impl::bin_chunk(BinChunk& ch, const DrawCall& draw, const DrawVertices& dv,
                               const Viewport& vp, const ClipBounds& bounds, int tiles_x,
                               int tiles_y) {
  ch.setups.clear();
  ch.pairs.clear();
  ch.culled = ch.clipped = 0;
  const uint32_t tiles = static_cast<uint32_t>(tiles_x * tiles_y);
  // Pairs every tile whose part of t's box holds a pixel of t with set-up `local`.
  auto bin = [&](const TriSetup& t, uint32_t local) {
    const int32_t tx0 = t.x0 / kTileSize, tx1 = t.xmax / kTileSize;
    const int32_t ty0 = t.y0 / kTileSize, ty1 = t.ymax / kTileSize;
    if (tx0 == tx1 && ty0 == ty1) {
      // Most triangles of a dense mesh lie in one tile: the tile kernel tests their edges
      // anyway, so testing them here too would only double the work.
      ch.pairs.push_back((static_cast<uint64_t>(ty0) * tiles_x + tx0) << 32 | local);
      return;
    }
    for (int32_t ty = ty0; ty <= ty1; ++ty)
      for (int32_t tx = tx0; tx <= tx1; ++tx) {
        TileEdges te;
        if (!tile_region_edges(t, tx * kTileSize, ty * kTileSize, te)) continue;
        const uint64_t tile = static_cast<uint64_t>(ty) * tiles_x + tx;
        ch.pairs.push_back((tile << 32) | local);
      }
  };
  // Triangles that need no clipping are set up side by side (setup_snapped_batch); one that
  // does flushes the batch first, so set-ups stay in submission order. The batch lives in the
  // chunk: initialised once, not per chunk and frame.
  SnappedBatch& batch = ch.batch;
  uint32_t* const batch_primitive = ch.batch_primitive;
  float* const batch_key = ch.batch_key;
  batch.count = 0;
  auto flush = [&] {
    if (batch.count == 0) return;
    const size_t base = ch.setups.size();
    ch.setups.resize(base + batch.count);
    uint8_t index[kSetupBatch];
    const uint32_t n = setup_snapped_batch(batch, vp, draw.state.cull, ch.setups.data() + base, index);
    ch.setups.resize(base + n);
    ch.culled += batch.count - n;
    for (uint32_t j = 0; j < n; ++j) {
      TriSetup& t = ch.setups[base + j];
      t.draw = ch.draw;
      t.primitive = batch_primitive[index[j]];
      t.sort_key = batch_key[index[j]];
      bin(t, static_cast<uint32_t>(base + j));
    }
    batch.count = 0;
  };
  ClipPolygon poly;
  const bool translucent = draw.state.blend != BlendMode::Opaque;
  const uint32_t group = std::max(draw.sort_group, 1u);
  // The current run's key (run_key), computed at the run's first triangle in this chunk.
  uint32_t keyed_run = std::numeric_limits<uint32_t>::max();
  float shared_key = 0.0f;
  for (uint32_t p = ch.first; p < ch.first + ch.count; ++p) {
    const uint32_t i0 = draw.indices[3 * size_t{p}], i1 = draw.indices[3 * size_t{p} + 1],
                   i2 = draw.indices[3 * size_t{p} + 2];
    if (i0 >= draw.vertex_count || i1 >= draw.vertex_count || i2 >= draw.vertex_count) {
      ++ch.culled;  // loaders reject such meshes; the rasterizer still never reads out of range
      continue;
    }
    const FrontVertex &f0 = dv.front[i0], &f1 = dv.front[i1], &f2 = dv.front[i2];
    const uint32_t c0 = f0.code, c1 = f1.code, c2 = f2.code;
    if (((c0 | c1 | c2) & kNonFinite) || (c0 & c1 & c2)) {
      ++ch.culled;
      continue;
    }
    // Only translucent triangles are ever sorted.
    float key = (f0.w + f1.w + f2.w) * (1.0f / 3.0f);
    if (translucent && draw.sort_keys) {
      key = draw.sort_keys[p];
    } else if (translucent) {
      const uint32_t run = p / group;
      if (run != keyed_run) {
        keyed_run = run;
        shared_key = run_key(draw, dv.front.data(), run * group, std::min(group, draw.triangle_count - run * group));
      }
      if (!std::isnan(shared_key)) key = shared_key;
    }
    if (!((c0 | c1 | c2) & kClipPlaneBits)) {
      const uint32_t b = batch.count++;
      const FrontVertex* f[3] = {&f0, &f1, &f2};
      for (int k = 0; k < 3; ++k) {
        batch.x[k][b] = f[k]->snap.x;
        batch.y[k][b] = f[k]->snap.y;
        batch.depth[k][b] = f[k]->snap.depth;
        batch.inv_w[k][b] = f[k]->snap.inv_w;
      }
      batch_primitive[b] = p;
      batch_key[b] = key;
      if (batch.count == kSetupBatch) flush();
      continue;
    }
    flush();
    if (clip_triangle(dv.clip[i0], dv.clip[i1], dv.clip[i2], bounds, poly) == ClipResult::Culled) {
      ++ch.culled;
      continue;
    }
    ++ch.clipped;
    bool any = false;
    for (int k = 1; k + 1 < poly.count; ++k) {
      TriSetup t;
      if (!setup_triangle(poly.v[0], poly.v[k], poly.v[k + 1], vp, draw.state.cull, t)) continue;
      t.draw = ch.draw;
      t.primitive = p;
      t.sort_key = key;
      const uint32_t local = static_cast<uint32_t>(ch.setups.size());
      ch.setups.push_back(t);
      bin(t, local);
      any = true;
    }
    if (!any) ++ch.culled;
  }
  flush();
  // Counting sort by tile; within a tile the items keep submission order.
  ch.tile_offsets.assign(tiles + 1, 0);
  for (uint64_t pr : ch.pairs) ++ch.tile_offsets[(pr >> 32) + 1];
  std::partial_sum(ch.tile_offsets.begin(), ch.tile_offsets.end(), ch.tile_offsets.begin());
  ch.items.resize(ch.pairs.size());
  // Stable scatter: walk pairs in order, writing at a running position per tile.
  std::vector<uint32_t>& pos = ch.tile_cursor;
  pos.assign(ch.tile_offsets.begin(), ch.tile_offsets.end() - 1);
  for (uint64_t pr : ch.pairs) ch.items[pos[pr >> 32]++] = static_cast<uint32_t>(pr);
}

void Renderer::Impl::front_end(std::span<const DrawCall> draws, const Viewport& vp, int tiles_x,
                               int tiles_y) {
  size_t n = 0;
  for (uint32_t d = 0; d < draws.size(); ++d)
    for (uint32_t f = 0; f < draws[d].triangle_count; f += kChunkTriangles) {
      if (chunks.size() <= n) chunks.emplace_back();
      BinChunk& ch = chunks[n++];
      ch.draw = d;
      ch.first = f;
      ch.count = std::min(kChunkTriangles, draws[d].triangle_count - f);
    }
  chunks.resize(n);
  if (n > kMaxChunks)
    throw std::length_error("render: " + std::to_string(n) + " chunks of " + std::to_string(kChunkTriangles) +
                            " triangles exceed the visibility buffer's " + std::to_string(kMaxChunks));
  const ClipBounds bounds = make_clip_bounds(vp.width, vp.height);
  pool.parallel_for(chunks.size(), [&](size_t c, int) {
    BinChunk& ch = chunks[c];
    bin_chunk(ch, draws[ch.draw], clip[ch.draw], vp, bounds, tiles_x, tiles_y);
  });
}

void Renderer::render(std::span<const DrawCall> draws, const RenderOptions& options,
                      const RenderTarget& target, RasterStats* stats) {
  if (target.width <= 0 || target.height <= 0 || target.width > kMaxImageSide ||
      target.height > kMaxImageSide)
    throw std::invalid_argument("render target size " + std::to_string(target.width) + "x" +
                                std::to_string(target.height) + " outside 1.." +
                                std::to_string(kMaxImageSide));
  for (size_t k = 0; k < draws.size(); ++k) {
    const DrawCall& d = draws[k];
    if (d.triangle_count > 0 && (!d.positions || !d.indices || !d.shader))
      throw std::invalid_argument("draw call without positions, indices or shader");
    if (d.varying_count > kMaxVaryings || (d.varying_count > 0 && !d.varyings))
      throw std::invalid_argument("draw call varyings: count above kMaxVaryings or no data");
    if (d.state.alpha_test && !(d.state.alpha_cutoff >= 0.0f && d.state.alpha_cutoff <= 1.0f))
      throw std::invalid_argument("draw call " + std::to_string(k) + ": alpha_cutoff " +
                                  std::to_string(d.state.alpha_cutoff) + " outside [0, 1]");
    // A blended draw has no test to pass: its alpha weighs the blend.
    if (d.state.alpha_test && d.state.blend != BlendMode::Opaque)
      throw std::invalid_argument("draw call " + std::to_string(k) + ": alpha_test on a blended draw");
  }
  Impl& im = *impl_;
  const auto t0 = Clock::now();
  const Viewport vp{target.width, target.height};
  const int tiles_x = (vp.width + kTileSize - 1) / kTileSize;
  const int tiles_y = (vp.height + kTileSize - 1) / kTileSize;
  im.transform(draws, vp);
  im.front_end(draws, vp, tiles_x, tiles_y);
  const double ms_front = ms_since(t0);

  const auto t1 = Clock::now();
  const uint32_t tiles = static_cast<uint32_t>(tiles_x * tiles_y);
  // Heaviest tiles first, so the last ones to finish are short; the order never changes
  // a pixel because tiles are independent.
  im.tile_order.resize(tiles);
  std::iota(im.tile_order.begin(), im.tile_order.end(), 0u);
  std::vector<uint32_t>& load = im.tile_load;
  load.assign(tiles, 0);
  for (const BinChunk& ch : im.chunks)
    for (uint32_t t = 0; t < tiles; ++t) load[t] += ch.tile_offsets[t + 1] - ch.tile_offsets[t];
  std::sort(im.tile_order.begin(), im.tile_order.end(),
            [&](uint32_t a, uint32_t b) { return load[a] > load[b] || (load[a] == load[b] && a < b); });

  while (im.scratch.size() < static_cast<size_t>(im.pool.slots())) {
    im.scratch.push_back(std::make_unique<TileScratch>());
    // Each visible entry owns at least one pixel of the tile.
    im.scratch.back()->visible.reserve(kTilePixels);
  }
  // Every worker's list of translucent items (and the tile sort's second buffer) is sized for
  // the heaviest tile now, not when a worker first meets such a tile: which worker takes
  // which tile varies from run to run, and a frame that renders again must not allocate.
  const uint32_t max_load = tiles > 0 ? *std::max_element(load.begin(), load.end()) : 0;
  for (auto& s : im.scratch) {
    s->fragments_visible = s->pixels_shaded = s->fragments_blended = s->lanes_shaded = 0;
    s->exact_passes = s->exact_fragments_peak = 0;
    if (s->translucent.capacity() < max_load) s->translucent.reserve(max_load);
    if (s->translucent_scratch.capacity() < max_load) s->translucent_scratch.reserve(max_load);
  }

  FrameView view;
  view.vp = vp;
  view.tiles_x = tiles_x;
  view.tiles_y = tiles_y;
  view.draws = draws.data();
  view.chunks = im.chunks.data();
  view.chunk_count = im.chunks.size();
  view.tile_load = load.data();
  view.options = options;
  view.target = target;
  if (target.color8)
    for (int32_t x = 0; x < kTileSize; ++x)
      for (int c = 0; c < 4; ++c) view.background8[4 * x + c] = unorm8(options.background[c]);
  im.pool.parallel_for(tiles, [&](size_t i, int slot) {
    raster_tile(view, im.tile_order[i], *im.scratch[slot]);
  });

  if (stats) {
    RasterStats st;
    for (const DrawCall& d : draws) st.triangles_submitted += d.triangle_count;
    for (const BinChunk& ch : im.chunks) {
      st.triangles_culled += ch.culled;
      st.triangles_clipped += ch.clipped;
      st.triangles_setup += ch.setups.size();
      st.bin_items += ch.items.size();
    }
    for (auto& s : im.scratch) {
      st.fragments_visible += s->fragments_visible;
      st.pixels_shaded += s->pixels_shaded;
      st.fragments_blended += s->fragments_blended;
      st.lanes_shaded += s->lanes_shaded;
      st.exact_passes += s->exact_passes;
      st.exact_fragments_peak = std::max(st.exact_fragments_peak, s->exact_fragments_peak);
    }
    st.ms_front = ms_front;
    st.ms_tiles = ms_since(t1);
    *stats = st;
  }
}

}  // namespace pelt::raster
