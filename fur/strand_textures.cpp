#include "fur/strand_textures.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace pelt::fur {
namespace {

// Uniform in [0, 1) from one raw mt19937 output.
struct Uniform {
  std::mt19937 engine;
  explicit Uniform(uint32_t seed) : engine(seed) {}
  double operator()() { return double(engine()) * (1.0 / 4294967296.0); }
};

// std::lround(clamp(v, 0, 1) * 255.0f) without the library call (an eighth of the textures'
// set-up): the float product lies in [0, 255] (NaN gives 0), where adding 0.5 in double is
// exact and truncating is flooring, so halves round up as lround's do.
uint8_t to8(float v) {
  const float c = v > 0.0f ? std::min(v, 1.0f) : 0.0f;
  return uint8_t(int(double(c * 255.0f) + 0.5));
}

int wrap(long v, int size) {
  long m = v % size;
  return int(m < 0 ? m + size : m);
}

void put(uint8_t* p, const glm::vec3& rgb, float alpha) {
  p[0] = to8(rgb.x);
  p[1] = to8(rgb.y);
  p[2] = to8(rgb.z);
  p[3] = to8(alpha);
}

// Writes a strand texel unless a strand with a larger alpha is already there, so the
// result does not depend on the order in which crossing strands are drawn.
void put_max(uint8_t* p, const glm::vec3& rgb, float alpha) {
  const uint8_t a = to8(alpha);
  if (a <= p[3]) return;
  put(p, rgb, alpha);
}

// put_max for the luminance form (ShellLuminance): the same alpha rule, so both forms keep
// the same strand where strands meet.
void put_max_la(uint8_t* p, float luminance, float alpha) {
  const uint8_t a = to8(alpha);
  if (a <= p[1]) return;
  p[0] = to8(luminance);
  p[1] = a;
}

glm::vec3 layer_colour(const FurParams& p, float h) {
  return p.root_color + (p.tip_color - p.root_color) * h;
}

}  // namespace

void strand_texel(const ShellStrand& strand, int s, int layers, int size, int& x, int& y) {
  const float h = layers > 1 ? float(s) / float(layers - 1) : 0.0f;
  const float rise = h * float(shell_volume_height(size)) / strand.seed.y;
  x = wrap(strand.root_x + std::lround(strand.seed.x * rise), size);
  y = wrap(strand.root_y + std::lround(strand.seed.z * rise), size);
}

float strand_alpha(const ShellStrand& strand, float h) {
  if (h > strand.length) return 0.0f;
  return 1.0f - 0.8f * (h / strand.length);
}

std::optional<ParamError> generate_strand_textures(const FurParams& params, StrandTextures& out, ShellForms forms) {
  if (auto e = validate(params)) return e;
  const int N = params.texture_size, S = params.shells;
  const size_t area = size_t(N) * size_t(N);
  const size_t roots = size_t(std::lround(double(params.density) / 100.0 * double(area)));

  Uniform rnd(params.seed);
  // Selection sampling (Knuth's algorithm S): visits texels in order and takes each with
  // probability (roots still needed) / (texels left), giving exactly `roots` distinct
  // roots with every subset equally likely.
  out.strands.clear();
  out.strands.reserve(roots);
  for (size_t t = 0; t < area && out.strands.size() < roots; ++t) {
    const double need = double(roots - out.strands.size());
    if (double(area - t) * rnd() >= need) continue;
    ShellStrand st;
    st.root_x = int(t % size_t(N));
    st.root_y = int(t / size_t(N));
    st.seed.x = float(2.0 * rnd() - 1.0);
    st.seed.z = float(2.0 * rnd() - 1.0);
    st.seed.y = float(2.0 + rnd());
    st.length = float(std::min(1.0, 0.6 + 0.5 * rnd()));
    st.brightness = float(0.75 + 0.5 * rnd());
    out.strands.push_back(st);
  }

  LayerTextures& sh = out.shells;
  sh.size = N;
  sh.layers = S;
  const bool rgba = forms == ShellForms::RgbaAndLuminance;
  sh.rgba.assign(rgba ? area * size_t(S) * 4 : 0, 0);
  ShellLuminance& lum = out.shell_luminance;
  lum.size = N;
  lum.layers = S;
  lum.la.assign(area * size_t(S) * 2, 0);
  lum.tint.resize(size_t(S));
  const uint8_t no_strand = to8(1.0f / kMaxStrandBrightness);
  // Opacity per layer for a re-sliced fur (FurParams::authored_shells); exponent 1 keeps the
  // authored alpha bit for bit.
  const int authored = params.authored_shells > 0 ? params.authored_shells : S;
  const double exponent = double(authored - 1) / double(S - 1);
  for (int s = 0; s < S; ++s) {
    const float h = float(s) / float(S - 1);
    const glm::vec3 base = layer_colour(params, h);
    uint8_t* layer = rgba ? sh.rgba.data() + size_t(s) * area * 4 : nullptr;
    uint8_t* la = lum.la.data() + size_t(s) * area * 2;
    lum.tint[size_t(s)] = base * kMaxStrandBrightness;
    for (size_t t = 0; t < area; ++t) {
      if (rgba) put(layer + 4 * t, base, 0.0f);
      la[2 * t] = no_strand;
    }
    for (const ShellStrand& st : out.strands) {
      float a = strand_alpha(st, h);
      if (a <= 0.0f) continue;
      if (authored != S) a = float(1.0 - std::pow(1.0 - double(a), exponent));
      int x, y;
      strand_texel(st, s, S, N, x, y);
      const size_t t = size_t(y) * N + size_t(x);
      if (rgba) put_max(layer + 4 * t, base * st.brightness, a);
      put_max_la(la + 2 * t, st.brightness / kMaxStrandBrightness, a);
    }
  }

  if (params.fins == FinMode::off) return std::nullopt;  // nothing draws a fin
  LayerTextures& fin = out.fin;
  fin.size = N;
  fin.layers = 1;
  fin.rgba.assign(area * 4, 0);
  FinLuminance& fin_lum = out.fin_luminance;
  fin_lum.size = N;
  fin_lum.la.assign(area * 2, 0);
  fin_lum.tint_root = params.root_color * kMaxStrandBrightness;
  fin_lum.tint_slope = (params.tip_color - params.root_color) * kMaxStrandBrightness;
  for (int y = 0; y < N; ++y) {
    const glm::vec3 base = layer_colour(params, (float(y) + 0.5f) / float(N));
    for (int x = 0; x < N; ++x) {
      put(fin.rgba.data() + (size_t(y) * N + size_t(x)) * 4, base, 0.0f);
      fin_lum.la[(size_t(y) * N + size_t(x)) * 2] = no_strand;
    }
  }
  Uniform frnd(params.seed ^ 0x9E3779B9u);  // an independent stream for the fin
  const long fin_strands =
      std::lround(double(params.density) / 100.0 * double(N) * double(kFinDepthTexels));
  for (long k = 0; k < fin_strands; ++k) {
    const double x0 = frnd() * N;
    const double lean = (2.0 * frnd() - 1.0) * 0.1 * N;
    const float length = float(std::min(1.0, 0.6 + 0.5 * frnd()));
    const float bright = float(0.75 + 0.5 * frnd());
    for (int y = 0; y < N; ++y) {
      const float v = (float(y) + 0.5f) / float(N);
      if (v > length) break;
      const int x = wrap(long(std::floor(x0 + lean * v)), N);
      put_max(fin.rgba.data() + (size_t(y) * N + size_t(x)) * 4,
              layer_colour(params, v) * bright, 1.0f - 0.8f * v / length);
      put_max_la(fin_lum.la.data() + (size_t(y) * N + size_t(x)) * 2, bright / kMaxStrandBrightness,
                 1.0f - 0.8f * v / length);
    }
  }
  return std::nullopt;
}

StrandTextures match_llvmpipe_textures(ShellForms forms) {
  // The harness's loops and float expressions, kept in its order of random draws.
  constexpr int W = 256, H = 256, L = 16;
  const float fur[3] = {0.80f, 0.58f, 0.36f};
  StrandTextures out;
  out.shells.size = W;
  out.shells.layers = L;
  const bool rgba = forms == ShellForms::RgbaAndLuminance;
  out.shells.rgba.assign(rgba ? size_t(W) * H * L * 4 : 0, 0);
  // The same shells as luminance and alpha (ShellLuminance): the harness's texel colour is
  // its layer's colour times the strand's brightness, so L = brightness / kMaxStrandBrightness
  // and tint = layer colour * kMaxStrandBrightness give it back within L's rounding.
  ShellLuminance& lum = out.shell_luminance;
  lum.size = W;
  lum.layers = L;
  lum.la.assign(size_t(W) * H * L * 2, 0);
  lum.tint.resize(L);
  // The harness's shading, darker toward the root, of its layers (f = s / (L - 1)) and of its fin
  // (f = v); and a texel's luminance, the same in every layer.
  constexpr float kShadeRoot = 0.45f, kShadeSlope = 0.55f;
  auto layer_shade = [](float f) { return kShadeRoot + kShadeSlope * f; };
  auto luminance_of = [](bool strand, float bright) { return to8((strand ? bright : 1.0f) / kMaxStrandBrightness); };
  for (int s = 0; s < L; ++s)
    lum.tint[size_t(s)] =
        glm::vec3(fur[0], fur[1], fur[2]) * (layer_shade(float(s) / (L - 1)) * kMaxStrandBrightness);
  Uniform rng(2008);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const bool strand = rng() < 0.30;
      const float bright = float(0.75 + 0.5 * rng());
      const uint8_t luminance = luminance_of(strand, bright);
      for (int s = 0; s < L; ++s) {
        const float f = float(s) / (L - 1);
        const float shade = layer_shade(f) * (strand ? bright : 1.0f);
        const uint8_t alpha = strand ? to8(1.0f - 0.8f * f) : 0;
        if (rgba) {
          uint8_t* p = &out.shells.rgba[((size_t(s) * H + y) * W + x) * 4];
          for (int c = 0; c < 3; ++c) p[c] = to8(fur[c] * shade);
          p[3] = alpha;
        }
        uint8_t* q = &lum.la[((size_t(s) * H + y) * W + x) * 2];
        q[0] = luminance;
        q[1] = alpha;
      }
    }
  }
  out.fin.size = W;
  out.fin.layers = 1;
  out.fin.rgba.assign(size_t(W) * H * 4, 0);
  // The fin's luminance form: its colour is fur * layer_shade(v) * brightness.
  FinLuminance& fin_lum = out.fin_luminance;
  fin_lum.size = W;
  fin_lum.la.assign(size_t(W) * H * 2, 0);
  fin_lum.tint_root = glm::vec3(fur[0], fur[1], fur[2]) * (kShadeRoot * kMaxStrandBrightness);
  fin_lum.tint_slope = glm::vec3(fur[0], fur[1], fur[2]) * (kShadeSlope * kMaxStrandBrightness);
  Uniform frng(7600);
  for (int x = 0; x < W; ++x) {
    const bool strand = frng() < 0.30;
    const float bright = float(0.75 + 0.5 * frng());
    const float len = float(0.6 + 0.4 * frng());
    const uint8_t luminance = luminance_of(strand, bright);  // the same down the column
    for (int y = 0; y < H; ++y) {
      const float v = (y + 0.5f) / H;
      const float shade = layer_shade(v) * (strand ? bright : 1.0f);
      uint8_t* p = &out.fin.rgba[(size_t(y) * W + x) * 4];
      for (int c = 0; c < 3; ++c) p[c] = to8(fur[c] * shade);
      p[3] = (strand && v <= len) ? to8(1.0f - 0.8f * v) : 0;
      uint8_t* q = &fin_lum.la[(size_t(y) * W + x) * 2];
      q[0] = luminance;
      q[1] = p[3];
    }
  }
  return out;
}

}  // namespace pelt::fur
