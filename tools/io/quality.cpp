#include "tools/io/quality.h"

#include <charconv>

namespace pelt::io {
namespace {

template <class E>
struct Named {
  std::string_view name;
  E value;
};

constexpr Named<fur::FinMode> kFins[] = {
    {"off", fur::FinMode::off}, {"all", fur::FinMode::all}, {"silhouette", fur::FinMode::silhouette}};
constexpr Named<FinQuads> kFinQuads[] = {{"layer", FinQuads::layer}, {"merged", FinQuads::merged}};
constexpr Named<SortQuality> kSorts[] = {{"none", SortQuality::none},
                                         {"layer", SortQuality::layer},
                                         {"tile", SortQuality::tile},
                                         {"surface", SortQuality::surface},
                                         {"exact", SortQuality::exact}};
constexpr Named<raster::Filter> kFilters[] = {{"nearest", raster::Filter::Nearest},
                                              {"bilinear", raster::Filter::Bilinear},
                                              {"bilinear_mip", raster::Filter::BilinearMip},
                                              {"trilinear", raster::Filter::Trilinear}};
// `off` is a material setting, not a quality level: turning the epidermis or dermis off
// changes what the skin is, so the knobs list only the approximations of each term.
constexpr Named<shading::MultipleScattering> kMultiple[] = {
    {"paper", shading::MultipleScattering::paper},
    {"normal_blur", shading::MultipleScattering::normal_blur},
    {"reference", shading::MultipleScattering::reference}};
constexpr Named<shading::SingleScattering> kSingle[] = {{"off", shading::SingleScattering::off},
                                                        {"paper", shading::SingleScattering::paper},
                                                        {"correct", shading::SingleScattering::correct}};
constexpr Named<Precision> kPrecisions[] = {{"simd", Precision::simd}, {"double", Precision::double_precision}};

template <class E, size_t N>
std::string list(const Named<E> (&table)[N]) {
  std::string s;
  for (size_t i = 0; i < N; ++i) s += (i ? ", " : "") + std::string(table[i].name);
  return s;
}

template <class E, size_t N>
std::optional<std::string> pick(const Named<E> (&table)[N], std::string_view value, E& out) {
  for (const auto& e : table)
    if (e.name == value) {
      out = e.value;
      return std::nullopt;
    }
  return "unknown value `" + std::string(value) + "` (" + list(table) + ")";
}

template <class E, size_t N>
std::string name_of(const Named<E> (&table)[N], E v) {
  for (const auto& e : table)
    if (e.value == v) return std::string(e.name);
  return "?";
}

std::optional<int> parse_int(std::string_view s) {
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

std::optional<std::string> set_knob(Quality& q, std::string_view knob, std::string_view value) {
  Quality n = q;
  std::optional<std::string> err;
  if (knob == "shells") {
    const auto v = parse_int(value);
    if (!v || *v < 2 || *v > 128) return "must be an integer in [2, 128], got `" + std::string(value) + "`";
    n.shells = *v;
  } else if (knob == "fins") {
    fur::FinMode m{};
    err = pick(kFins, value, m);
    n.fins = m;
  } else if (knob == "fin_quads") {
    err = pick(kFinQuads, value, n.fin_quads);
  } else if (knob == "sort") {
    err = pick(kSorts, value, n.sort);
  } else if (knob == "spp") {
    const auto v = parse_int(value);
    int side = 1;
    while (v && side < kMaxSppSide && side * side < *v) ++side;
    if (!v || *v < 1 || side * side != *v)
      return "must be a square number of samples from 1 to 64 (1, 4, 9, 16, 25, 36, 49, 64), got `" +
             std::string(value) + "`";
    n.spp = *v;
  } else if (knob == "filter") {
    err = pick(kFilters, value, n.filter);
  } else if (knob == "multiple_scattering") {
    shading::MultipleScattering m{};
    err = pick(kMultiple, value, m);
    n.multiple_scattering = m;
  } else if (knob == "single_scattering") {
    shading::SingleScattering m{};
    err = pick(kSingle, value, m);
    n.single_scattering = m;
  } else if (knob == "precision") {
    err = pick(kPrecisions, value, n.precision);
  } else {
    std::string all;
    for (std::string_view k : kKnobs) all += (all.empty() ? "" : ", ") + std::string(k);
    return "unknown quality knob `" + std::string(knob) + "` (" + all + ")";
  }
  if (err) return err;
  q = n;
  return std::nullopt;
}

std::string knob_value(const Quality& q, std::string_view knob) {
  if (knob == "shells") return q.shells ? std::to_string(*q.shells) : "scene";
  if (knob == "fins") return q.fins ? name_of(kFins, *q.fins) : "scene";
  if (knob == "fin_quads") return name_of(kFinQuads, q.fin_quads);
  if (knob == "sort") return name_of(kSorts, q.sort);
  if (knob == "spp") return std::to_string(q.spp);
  if (knob == "filter") return name_of(kFilters, q.filter);
  if (knob == "multiple_scattering")
    return q.multiple_scattering ? name_of(kMultiple, *q.multiple_scattering) : "scene";
  if (knob == "single_scattering") return q.single_scattering ? name_of(kSingle, *q.single_scattering) : "scene";
  if (knob == "precision") return name_of(kPrecisions, q.precision);
  return "?";
}

std::vector<std::string> knob_sweep(std::string_view knob) {
  if (knob == "shells") return {"4", "8", "16", "32", "64"};
  if (knob == "fins") return {"off", "all", "silhouette"};
  if (knob == "fin_quads") return {"layer", "merged"};
  if (knob == "sort") return {"none", "layer", "tile", "surface", "exact"};
  if (knob == "spp") return {"1", "4", "16"};
  if (knob == "filter") return {"nearest", "bilinear", "bilinear_mip", "trilinear"};
  if (knob == "multiple_scattering") return {"paper", "normal_blur", "reference"};
  if (knob == "single_scattering") return {"off", "paper", "correct"};
  if (knob == "precision") return {"simd", "double"};
  return {};
}

std::optional<Quality> quality_preset(std::string_view name) {
  Quality q;
  if (name == "default") return q;
  // Chosen from `pelt tradeoff` on the fur box and the skin head (README, "What accuracy
  // costs"): each lies on or next to the measured Pareto front of both.
  if (name == "fast") {  // 8 layers, one mip level; the scene's fins and sort
    q.shells = 8;
    // The nearest level costs what level 0 costs and does not alias minified fur (README).
    q.filter = raster::Filter::BilinearMip;
    // Fins off and no sort as well took 0.76x this preset's time for 1.8x its error on the
    // furry box (measurement log, 2026-11-26, later): off the front, where 4 shells with
    // fins and the tile sort were both faster and closer.
    return q;
  }
  if (name == "balanced") {  // the scene's fins and sort, twice the layers, the physical skin terms
    q.shells = 32;
    q.multiple_scattering = shading::MultipleScattering::reference;
    q.single_scattering = shading::SingleScattering::correct;
    return q;
  }
  if (name == "high") {  // the reference's layers, sort and fins, 4 samples a pixel
    q.shells = 64;
    q.fin_quads = FinQuads::layer;
    q.sort = SortQuality::exact;
    q.spp = 4;
    q.multiple_scattering = shading::MultipleScattering::reference;
    q.single_scattering = shading::SingleScattering::correct;
    return q;
  }
  if (name == "reference") {
    q.shells = 64;
    q.fin_quads = FinQuads::layer;  // eq. 1's fins, one quad per pair of layers
    q.sort = SortQuality::exact;
    q.spp = kMaxSppSide * kMaxSppSide;
    // Level 0 bilinear under 64 samples a pixel: the texture is filtered by the
    // supersampling itself, not by a mip level's box filter.
    q.filter = raster::Filter::Bilinear;
    q.multiple_scattering = shading::MultipleScattering::reference;
    q.single_scattering = shading::SingleScattering::correct;
    q.precision = Precision::double_precision;
    q.exact_physics = true;
    return q;
  }
  return std::nullopt;
}

std::vector<std::string_view> quality_preset_names() { return {"default", "fast", "balanced", "high", "reference"}; }

std::string describe(const Quality& q) {
  std::string s;
  for (std::string_view k : kKnobs) {
    if (!s.empty()) s += ' ';
    s += k;
    s += '=';
    s += knob_value(q, k);
  }
  if (q.exact_physics) s += " physics=exact";
  return s;
}

}  // namespace pelt::io
