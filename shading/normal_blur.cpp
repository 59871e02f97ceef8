#include "shading/normal_blur.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
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
// improvement. An entry is one 128-bit key, the distance's bits above the vertex: distances are
// finite and >= 0 (the source's is +0), where the bits order as the doubles do, so one integer
// comparison orders (distance, vertex) without a branch, and the smallest of four children is
// picked by conditional moves. With (double, vertex) pairs compared by branches, whose outcomes
// the processor cannot predict, the blur of sphere:256 took 13.0-13.5 s on one thread; now
// 7.4-7.7 s, the same bits.
class TentativeHeap {
 public:
  explicit TentativeHeap(size_t vertices) : slot_(vertices, kAbsent) {}
  bool empty() const { return keys_.empty(); }
  bool contains(uint32_t v) const { return slot_[v] != kAbsent; }
  void push(double d, uint32_t v) {
    keys_.push_back(key(d, v));
    up(keys_.size() - 1);
  }
  void decrease(double d, uint32_t v) { up(slot_[v], key(d, v)); }
  // Removes and returns the nearest vertex and its distance.
  std::pair<double, uint32_t> pop() {
    const Key top = keys_[0];
    const uint32_t v = uint32_t(top);
    slot_[v] = kAbsent;
    const Key last = keys_.back();
    keys_.pop_back();
    if (!keys_.empty()) down(last);
    return {std::bit_cast<double>(uint64_t(top >> 32)), v};
  }
  // Drops every tentative vertex (a search stopped early).
  void clear() {
    for (const Key k : keys_) slot_[uint32_t(k)] = kAbsent;
    keys_.clear();
  }

 private:
  using Key = unsigned __int128;
  static constexpr uint32_t kAbsent = UINT32_MAX;
  static Key key(double d, uint32_t v) { return (Key(std::bit_cast<uint64_t>(d)) << 32) | v; }
  void place(size_t i, Key k) {
    keys_[i] = k;
    slot_[uint32_t(k)] = uint32_t(i);
  }
  void up(size_t i) { up(i, keys_[i]); }
  // Puts k, whose place i may be too low, where it belongs above it.
  void up(size_t i, Key k) {
    while (i > 0) {
      const size_t parent = (i - 1) / 4;
      if (!(k < keys_[parent])) break;
      place(i, keys_[parent]);
      i = parent;
    }
    place(i, k);
  }
  // Puts k at the root, which it replaces, and sifts it down.
  void down(Key k) {
    size_t i = 0;
    const size_t n = keys_.size();
    for (;;) {
      const size_t first = 4 * i + 1;
      if (first >= n) break;
      size_t best = first;
      Key b = keys_[first];
      const size_t end = std::min(first + 4, n);
      for (size_t c = first + 1; c < end; ++c) {
        const Key kc = keys_[c];
        const bool less = kc < b;
        best = less ? c : best;
        b = less ? kc : b;
      }
      if (!(b < k)) break;
      place(i, b);
      i = best;
    }
    place(i, k);
  }
  std::vector<Key> keys_;
  std::vector<uint32_t> slot_;
};

// The welded vertices' edges as compressed rows: vertex v's neighbours are to[row[v]] to
// to[row[v + 1] - 1], at edge lengths len[...].
struct Graph {
  std::vector<size_t> row;
  std::vector<uint32_t> to;
  std::vector<double> len;
};

// One edge-path search's state, sized to the whole graph. Each search leaves it clean (it resets
// only the vertices it touched), so a state serves search after search. States are made once
// per worker (StatePool), not once per item: filling `best` and the heap's slots for every item
// of 128 sources cost W^2 / 128 writes of 12 bytes, quadratic in the vertex count whatever the
// radius (sphere:2048 at a radius that reaches no neighbour: 21.7 s, now 2.8 s).
struct SearchState {
  explicit SearchState(size_t vertices) : best(vertices, INFINITY), queue(vertices) {}
  std::vector<double> best;
  std::vector<uint32_t> touched;
  TentativeHeap queue;
};

// Dijkstra from `s` along the edges, out to `cutoff`: settle(d, v) for each vertex within it, in
// (distance, vertex) order, at most `limit` of them. Returns how many settled.
template <class Settle>
size_t search(const Graph& g, SearchState& st, uint32_t s, double cutoff, size_t limit, Settle&& settle) {
  size_t settled = 0;
  st.best[s] = 0.0;
  st.touched.push_back(s);
  st.queue.push(0.0, s);
  while (!st.queue.empty() && settled < limit) {
    const auto [d, v] = st.queue.pop();
    ++settled;
    settle(d, v);
    for (size_t e = g.row[v]; e < g.row[v + 1]; ++e) {
      const uint32_t u = g.to[e];
      const double nd = d + g.len[e];
      if (nd <= cutoff && nd < st.best[u]) {
        // Settled vertices never improve (their distance is at most d); a tentative one moves
        // up, a new one enters.
        if (st.queue.contains(u)) {
          st.queue.decrease(nd, u);
        } else {
          st.touched.push_back(u);
          st.queue.push(nd, u);
        }
        st.best[u] = nd;
      }
    }
  }
  st.queue.clear();
  for (uint32_t t : st.touched) st.best[t] = INFINITY;
  st.touched.clear();
  return settled;
}

// The search states of one blur_normals call: an item takes one and gives it back, so there
// are as many as items ever ran at once (the threads of `parallel`). Which state an item gets
// does not matter: each is clean between searches.
class StatePool {
 public:
  explicit StatePool(size_t vertices) : vertices_(vertices) {}
  std::unique_ptr<SearchState> take() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<SearchState> s = std::move(free_.back());
        free_.pop_back();
        return s;
      }
    }
    return std::make_unique<SearchState>(vertices_);
  }
  void give_back(std::unique_ptr<SearchState> s) {
    const std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(s));
  }

 private:
  size_t vertices_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<SearchState>> free_;
};

void for_items(const ParallelFor& parallel, size_t count, const std::function<void(size_t)>& fn) {
  if (parallel) {
    parallel(count, fn);
  } else {
    for (size_t k = 0; k < count; ++k) fn(k);
  }
}

// "more than the budget of N pairs (raise it with FLAG)", the tail of every budget refusal.
std::string over_pair_budget(const NormalBlurBudget& budget) {
  std::string s = "more than the budget of " + std::to_string(budget.max_pairs) + " pairs";
  if (!budget.flag.empty()) s += " (raise it with " + budget.flag + ")";
  return s;
}

// Refuses, before any blur search, a mesh whose searches would settle more than
// budget.max_pairs (source, neighbour) pairs. kPairSamples evenly spaced sources are searched out
// to the cut-off, counting what they settle, and the pairs are estimated as W times their mean
// (`pairs`, set whether or not it refuses). The estimate is made even when W^2 pairs would fit,
// for the user to see (BlurredNormals::pair_estimate), at 64 searches of the blur's W. Each
// sample stops at `cap` vertices: one sample that reaches it alone puts the estimate over the
// budget, so the cap never changes the answer, and it bounds this check's cost by
// kPairSamples * min(W, cap) settled vertices (at most about sqrt(kPairSamples * max_pairs) per
// sample).
constexpr size_t kPairSamples = 64;
std::optional<ParamError> check_pair_estimate(const Graph& g, size_t W, double cutoff, const NormalBlurBudget& budget,
                                              StatePool& pool, const ParallelFor& parallel, uint64_t& pairs) {
  const uint64_t max_pairs = budget.max_pairs;
  pairs = 0;
  if (W == 0) return std::nullopt;
  const size_t samples = std::min(W, kPairSamples);
  const uint64_t per = max_pairs / W;  // each vertex's share, rounded down
  const uint64_t cap = per >= W / samples ? W : std::min<uint64_t>(W, (per + 1) * samples);
  std::vector<uint64_t> counts(samples, 0);
  for_items(parallel, samples, [&](size_t j) {
    std::unique_ptr<SearchState> st = pool.take();
    const uint32_t s = uint32_t((2 * uint64_t(j) + 1) * W / (2 * samples));
    counts[j] = search(g, *st, s, cutoff, size_t(cap), [](double, uint32_t) {});
    pool.give_back(std::move(st));
  });
  uint64_t sum = 0;
  for (uint64_t c : counts) sum += c;
  const unsigned __int128 total = (static_cast<unsigned __int128>(W) * sum + samples - 1) / samples;
  pairs = total > UINT64_MAX ? UINT64_MAX : uint64_t(total);
  if (total <= max_pairs) return std::nullopt;
  const uint64_t each = (sum + samples - 1) / samples;
  const bool capped = cap < W && std::find(counts.begin(), counts.end(), cap) != counts.end();
  const std::string about = capped ? "at least " : "about ";
  return ParamError{"normal_blur_radius",
                    "reaches " + about + std::to_string(pairs) + " (source, neighbour) vertex pairs, " +
                        over_pair_budget(budget) + ": a search out to 3 x " + format_number(cutoff / 3.0) +
                        " along the mesh's edges settles " + about + std::to_string(each) + " of its " +
                        std::to_string(W) + " welded vertices (the mean of " + std::to_string(samples) +
                        " evenly spaced ones); a smaller radius reaches fewer"};
}

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
                                       const ParallelFor& parallel, const NormalBlurBudget& budget) {
  for (auto& ch : out.channel) ch.clear();
  out.pair_estimate = 0;
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
  Graph g;
  g.row.assign(W + 1, 0);
  for (const auto& e : edges) ++g.row[e.first + 1];
  for (size_t i = 0; i < W; ++i) g.row[i + 1] += g.row[i];
  g.to.resize(edges.size());
  g.len.resize(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    g.to[i] = edges[i].second;
    g.len[i] = dist(m.positions + 3 * size_t(first[edges[i].first]), m.positions + 3 * size_t(first[edges[i].second]));
  }
  edges = {};

  const double smax = std::max({double(sigma[0]), double(sigma[1]), double(sigma[2])});
  std::vector<double> blurred(3 * 3 * W, 0.0);  // [channel][welded vertex][xyz]
  if (smax > 0.0) {
    const double cutoff = 3.0 * smax;
    StatePool pool(W);
    const uint64_t max_pairs = budget.max_pairs;
    if (auto e = check_pair_estimate(g, W, cutoff, budget, pool, parallel, out.pair_estimate)) return e;
    if (budget.estimate_only) return std::nullopt;
    // One Dijkstra search per welded vertex, each independent of the others, in items of
    // kItemVertices sources. The searches count the pairs they settle, and stop once the count
    // passes the budget (the estimate above can miss a dense part of a mesh); whether it
    // passes depends only on the mesh and sigma, not on the order the items ran in.
    constexpr size_t kItemVertices = 128;
    std::atomic<uint64_t> settled{0};
    std::atomic<bool> over{false};
    // An item adds its count to `settled` when done, or sooner once it holds a million pairs.
    auto add = [&](uint64_t& count) {
      if (settled.fetch_add(count, std::memory_order_relaxed) + count > max_pairs)
        over.store(true, std::memory_order_relaxed);
      count = 0;
    };
    auto item = [&](size_t k) {
      std::unique_ptr<SearchState> st = pool.take();
      uint64_t count = 0;
      const size_t end = std::min(W, (k + 1) * kItemVertices);
      for (size_t s = k * kItemVertices; s < end && !over.load(std::memory_order_relaxed); ++s) {
        double acc[3][3] = {};
        const size_t n = search(g, *st, uint32_t(s), cutoff, SIZE_MAX, [&](double d, uint32_t v) {
          double w = 0.0;
          for (int c = 0; c < 3; ++c) {
            const double sg = sigma[c];
            if (sg <= 0.0 || d > 3.0 * sg) continue;
            // A channel with the previous one's sigma has its weight (one exp, not three, when
            // a scene gives all three the same radius).
            if (!(c > 0 && sigma[c] == sigma[c - 1])) w = area[v] * std::exp(-d * d / (2.0 * sg * sg));
            for (int a = 0; a < 3; ++a) acc[c][a] += w * nrm[3 * v + a];
          }
        });
        count += n;
        if (count >= (uint64_t{1} << 20)) add(count);
        for (int c = 0; c < 3; ++c)
          for (int a = 0; a < 3; ++a) blurred[(c * W + s) * 3 + a] = acc[c][a];
      }
      add(count);
      pool.give_back(std::move(st));
    };
    for_items(parallel, (W + kItemVertices - 1) / kItemVertices, item);
    if (settled.load() > max_pairs)
      return ParamError{"normal_blur_radius",
                        "the searches out to 3 x " + format_number(smax) +
                            " along the mesh's edges settle more (source, neighbour) vertex pairs among its " +
                            std::to_string(W) + " welded vertices than the estimate from sampled vertices said " +
                            "(the mesh is denser where they missed), " +
                            over_pair_budget(budget) + "; a smaller radius reaches fewer"};
  }
  if (budget.estimate_only) return std::nullopt;

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
