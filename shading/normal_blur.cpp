#include "shading/normal_blur.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <unordered_map>
#include <utility>

namespace pelt::shading {
namespace {

struct Key {
  uint32_t x, y, z;
  bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    return (size_t(k.x) * 73856093u) ^ (size_t(k.y) * 19349663u) ^ (size_t(k.z) * 83492791u);
  }
};

uint32_t bits(float f) {
  if (f == 0.0f) f = 0.0f;  // +0 and -0 weld
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

double dist(const float* a, const float* b) {
  const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// The vertices whose distance is still tentative, as a 4-ary min-heap ordered by (distance,
// vertex): the order std::priority_queue of (distance, vertex) pairs gave, so vertices settle
// in the same sequence and the sums below are the same bits. Each vertex holds one entry,
// moved up when a shorter path is found (`slot` knows where), instead of a stale entry per
// improvement; the heap's sifting was most of the blur's time.
class TentativeHeap {
 public:
  explicit TentativeHeap(size_t vertices) : slot_(vertices, kAbsent) {}
  bool empty() const { return entries_.empty(); }
  bool contains(uint32_t v) const { return slot_[v] != kAbsent; }
  void push(double d, uint32_t v) {
    slot_[v] = uint32_t(entries_.size());
    entries_.push_back({d, v});
    up(entries_.size() - 1);
  }
  void decrease(double d, uint32_t v) {
    entries_[slot_[v]].d = d;
    up(slot_[v]);
  }
  // Removes and returns the nearest vertex and its distance.
  std::pair<double, uint32_t> pop() {
    const Entry top = entries_[0];
    slot_[top.v] = kAbsent;
    const Entry last = entries_.back();
    entries_.pop_back();
    if (!entries_.empty()) {
      entries_[0] = last;
      slot_[last.v] = 0;
      down(0);
    }
    return {top.d, top.v};
  }

 private:
  struct Entry {
    double d;
    uint32_t v;
  };
  static constexpr uint32_t kAbsent = UINT32_MAX;
  static bool before(const Entry& a, const Entry& b) { return a.d < b.d || (a.d == b.d && a.v < b.v); }
  void place(size_t i, const Entry& e) {
    entries_[i] = e;
    slot_[e.v] = uint32_t(i);
  }
  void up(size_t i) {
    const Entry e = entries_[i];
    while (i > 0) {
      const size_t parent = (i - 1) / 4;
      if (!before(e, entries_[parent])) break;
      place(i, entries_[parent]);
      i = parent;
    }
    place(i, e);
  }
  void down(size_t i) {
    const Entry e = entries_[i];
    const size_t n = entries_.size();
    for (;;) {
      const size_t first = 4 * i + 1;
      if (first >= n) break;
      size_t best = first;
      for (size_t c = first + 1; c < std::min(first + 4, n); ++c)
        if (before(entries_[c], entries_[best])) best = c;
      if (!before(entries_[best], e)) break;
      place(i, entries_[best]);
      i = best;
    }
    place(i, e);
  }
  std::vector<Entry> entries_;
  std::vector<uint32_t> slot_;
};

// The normal of each welded position, given each source vertex's share of its triangles' areas.
// A position counts once however many copies it has: copies that agree (a UV seam) give their
// unit normal as is, the same bits as the unsplit mesh; copies that differ (a crease) give the
// mean of their unit normals weighted by the areas of their own triangles, which does not
// change when a side is split into more copies. A copy without a normal (length 0) is left out.
std::vector<double> welded_normals(const NormalBlurInput& m, const std::vector<uint32_t>& rep, size_t W,
                                   const std::vector<double>& corner_area) {
  enum : uint8_t { kNone, kAgree, kDiffer };
  std::vector<double> nrm(3 * W, 0.0), mixed(3 * W, 0.0), mixed_area(W, 0.0);
  std::vector<uint8_t> state(W, kNone);
  for (size_t v = 0; v < m.vertex_count; ++v) {
    const float* n = m.normals + 3 * v;
    const double len = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
    if (!(len > 0)) continue;
    const double u[3] = {n[0] / len, n[1] / len, n[2] / len};
    const uint32_t w = rep[v];
    double* o = &nrm[3 * w];
    if (state[w] == kNone) {
      std::copy(u, u + 3, o);
      state[w] = kAgree;
    } else if (!std::equal(u, u + 3, o)) {
      state[w] = kDiffer;
    }
    for (int a = 0; a < 3; ++a) mixed[3 * w + a] += corner_area[v] * u[a];
    mixed_area[w] += corner_area[v];
  }
  for (size_t w = 0; w < W; ++w)
    if (state[w] == kDiffer)
      for (int a = 0; a < 3; ++a) nrm[3 * w + a] = mixed_area[w] > 0 ? mixed[3 * w + a] / mixed_area[w] : 0.0;
  return nrm;
}

}  // namespace

std::optional<ParamError> blur_normals(const NormalBlurInput& m, const float sigma[3], BlurredNormals& out,
                                       const ParallelFor& parallel) {
  for (auto& ch : out.channel) ch.clear();
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(sigma[c]) || sigma[c] < 0.0f)
      return ParamError{"normal_blur_radius[" + std::to_string(c) + "]", "must be finite and >= 0"};
  if (m.index_count % 3 != 0) return ParamError{"indices", "count must be a multiple of 3"};
  if (m.vertex_count > 0 && (!m.positions || !m.normals)) return ParamError{"positions", "null with vertices"};
  if (m.index_count > 0 && !m.indices) return ParamError{"indices", "null with a non-zero count"};
  const size_t V = m.vertex_count;
  for (size_t i = 0; i < 3 * V; ++i) {
    if (!std::isfinite(m.positions[i])) return ParamError{"positions", "vertex " + std::to_string(i / 3) + " is not finite"};
    if (!std::isfinite(m.normals[i])) return ParamError{"normals", "vertex " + std::to_string(i / 3) + " is not finite"};
  }
  for (size_t i = 0; i < m.index_count; ++i)
    if (m.indices[i] >= V)
      return ParamError{"indices", "index " + std::to_string(i) + " = " + std::to_string(m.indices[i]) +
                                       " is out of range (" + std::to_string(V) + " vertices)"};

  // Weld coincident positions: `rep[v]` is the welded vertex id.
  std::vector<uint32_t> rep(V);
  std::vector<uint32_t> first;  // welded id -> a source vertex
  {
    std::unordered_map<Key, uint32_t, KeyHash> ids;
    ids.reserve(V * 2);
    for (size_t v = 0; v < V; ++v) {
      const float* p = m.positions + 3 * v;
      auto [it, inserted] = ids.emplace(Key{bits(p[0]), bits(p[1]), bits(p[2])}, uint32_t(first.size()));
      if (inserted) first.push_back(uint32_t(v));
      rep[v] = it->second;
    }
  }
  const size_t W = first.size();

  // Vertex areas: per welded position (its weight) and per source vertex (its copy's share).
  std::vector<double> area(W, 0.0), corner_area(V, 0.0);
  // Adjacency as compressed rows of (neighbour, edge length).
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(m.index_count * 2);
  for (size_t t = 0; t + 2 < m.index_count; t += 3) {
    const uint32_t w[3] = {rep[m.indices[t]], rep[m.indices[t + 1]], rep[m.indices[t + 2]]};
    const float* p0 = m.positions + 3 * size_t(m.indices[t]);
    const float* p1 = m.positions + 3 * size_t(m.indices[t + 1]);
    const float* p2 = m.positions + 3 * size_t(m.indices[t + 2]);
    const double e1[3] = {double(p1[0]) - p0[0], double(p1[1]) - p0[1], double(p1[2]) - p0[2]};
    const double e2[3] = {double(p2[0]) - p0[0], double(p2[1]) - p0[1], double(p2[2]) - p0[2]};
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                 cz = e1[0] * e2[1] - e1[1] * e2[0];
    const double a3 = 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz) / 3.0;
    for (int k = 0; k < 3; ++k) {
      area[w[k]] += a3;
      corner_area[m.indices[t + k]] += a3;
      if (w[k] != w[(k + 1) % 3]) {
        edges.emplace_back(w[k], w[(k + 1) % 3]);
        edges.emplace_back(w[(k + 1) % 3], w[k]);
      }
    }
  }
  const std::vector<double> nrm = welded_normals(m, rep, W, corner_area);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<size_t> row(W + 1, 0);
  for (const auto& e : edges) ++row[e.first + 1];
  for (size_t i = 0; i < W; ++i) row[i + 1] += row[i];
  std::vector<double> elen(edges.size());
  for (size_t i = 0; i < edges.size(); ++i)
    elen[i] = dist(m.positions + 3 * size_t(first[edges[i].first]), m.positions + 3 * size_t(first[edges[i].second]));

  const double smax = std::max({double(sigma[0]), double(sigma[1]), double(sigma[2])});
  std::vector<double> blurred(3 * 3 * W, 0.0);  // [channel][welded vertex][xyz]
  if (smax > 0.0) {
    const double cutoff = 3.0 * smax;
    // One Dijkstra search per welded vertex, each independent of the others: items of
    // kItemVertices sources, each with its own search state (a search touches a few hundred
    // vertices, so resetting only those keeps `best` cheap to reuse within an item).
    constexpr size_t kItemVertices = 128;
    auto item = [&](size_t k) {
      std::vector<double> best(W, INFINITY);
      std::vector<uint32_t> touched;
      TentativeHeap queue(W);
      const size_t end = std::min(W, (k + 1) * kItemVertices);
      for (size_t s = k * kItemVertices; s < end; ++s) {
        double acc[3][3] = {};
        best[s] = 0.0;
        touched.push_back(uint32_t(s));
        queue.push(0.0, uint32_t(s));
        while (!queue.empty()) {
          const auto [d, v] = queue.pop();
          for (int c = 0; c < 3; ++c) {
            const double sg = sigma[c];
            if (sg <= 0.0 || d > 3.0 * sg) continue;
            const double w = area[v] * std::exp(-d * d / (2.0 * sg * sg));
            for (int a = 0; a < 3; ++a) acc[c][a] += w * nrm[3 * v + a];
          }
          for (size_t e = row[v]; e < row[v + 1]; ++e) {
            const uint32_t u = edges[e].second;
            const double nd = d + elen[e];
            if (nd <= cutoff && nd < best[u]) {
              // Settled vertices never improve (their distance is at most d); a tentative
              // one moves up, a new one enters.
              if (queue.contains(u)) {
                queue.decrease(nd, u);
              } else {
                touched.push_back(u);
                queue.push(nd, u);
              }
              best[u] = nd;
            }
          }
        }
        for (uint32_t t : touched) best[t] = INFINITY;
        touched.clear();
        for (int c = 0; c < 3; ++c)
          for (int a = 0; a < 3; ++a) blurred[(c * W + s) * 3 + a] = acc[c][a];
      }
    };
    const size_t items = (W + kItemVertices - 1) / kItemVertices;
    if (parallel) {
      parallel(items, item);
    } else {
      for (size_t k = 0; k < items; ++k) item(k);
    }
  }

  for (int c = 0; c < 3; ++c) {
    out.channel[c].resize(3 * V);
    for (size_t v = 0; v < V; ++v) {
      const float* n = m.normals + 3 * v;
      float* o = out.channel[c].data() + 3 * v;
      const double* b = blurred.data() + (c * W + rep[v]) * 3;
      const double len = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
      if (sigma[c] <= 0.0f || !(len > 1e-300)) {
        std::copy(n, n + 3, o);  // radius 0, or the neighbourhood's normals cancel: keep the input
        continue;
      }
      for (int a = 0; a < 3; ++a) o[a] = float(b[a] / len);
    }
  }
  return std::nullopt;
}

}  // namespace pelt::shading
