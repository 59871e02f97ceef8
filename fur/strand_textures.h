// Shell and fin textures grown from random seed vectors (seed 3.1.2).
//
// The S shell textures are read as one volume: x, y in the texture plane, height h =
// s/(S-1) up through the layers. Each strand starts at a root texel of layer 0 and has
// a seed vector (x, Y, z) with a large up component Y (the seed's "green must be high");
// its texel in layer s is where the seed vector's height equals the layer's height, so
// strands slant. Base levels only: the rasterizer builds the mip chains.
//
// Format (for the rasterizer): RGBA8, 4 bytes per texel in R, G, B, A order, STRAIGHT
// (not premultiplied) alpha, rows of `size` texels, row 0 = t = 0, layer after layer.
// Texels without a strand carry the layer's fur colour with alpha 0, so bilinear and
// mip filtering of straight alpha does not pull dark fringes into the strands.
//
// Randomness: std::mt19937 raw outputs divided by 2^32 (the engine's sequence is fixed
// by the C++ standard; <random> distributions are not), so a seed gives the same
// textures with every standard library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "fur/fur_params.h"

namespace pelt::fur {

struct LayerTextures {
  int size = 0;    // width = height, texels
  int layers = 0;  // 1 for the fin texture
  std::vector<uint8_t> rgba;  // layers * size * size * 4 bytes

  const uint8_t* layer(int s) const { return rgba.data() + size_t(s) * size * size * 4; }
  const uint8_t* texel(int s, int x, int y) const {
    return rgba.data() + ((size_t(s) * size + size_t(y)) * size + size_t(x)) * 4;
  }
};

// One shell strand: root texel, seed vector, length and brightness.
struct ShellStrand {
  int root_x = 0, root_y = 0;
  glm::vec3 seed{0.0f, 1.0f, 0.0f};  // x, z in [-1, 1], Y (up) in [2, 3]
  float length = 1.0f;               // fraction of the full fur height: min(1, 0.6 + 0.5 u), so
                                     // lengths spread over [0.6, 1] and a fifth reach the top layer
  float brightness = 1.0f;           // [0.75, 1.25]
};

// Height of the shell volume in texels: the horizontal offset of a strand at height h is
// (seed.x, seed.z) / seed.y * h * volume_height, at most half the volume height.
inline int shell_volume_height(int size) { return size / 16; }

// The texel of `strand` in layer s of S (wrapped into [0, size)), and its alpha there
// (1 at the root falling to 0.2 at its tip; 0 above its length). The generator writes
// exactly these; where strands meet the larger alpha wins.
void strand_texel(const ShellStrand& strand, int s, int layers, int size, int& x, int& y);
float strand_alpha(const ShellStrand& strand, float h);

// Strand brightness lies in [0.75, kMaxStrandBrightness].
inline constexpr float kMaxStrandBrightness = 1.25f;

// The shells as luminance and alpha: every shell texel's colour is its layer's colour times
// a brightness (1 where no strand is), so a layer needs only L = brightness /
// kMaxStrandBrightness and the alpha, 2 bytes a texel, and colour = min(1, tint * L) per
// channel with tint = layer colour * kMaxStrandBrightness. The renderer samples these as
// raster::TexelFormat::La8, about 1.4x faster than RGBA. Against `shells` the colour differs
// only by the rounding of L to 8 bits (at most 0.63/255 of a channel).
struct ShellLuminance {
  int size = 0;
  int layers = 0;
  std::vector<uint8_t> la;       // layers * size * size * 2 bytes: L, A, layer after layer
  std::vector<glm::vec3> tint;   // per layer
};

// The fin texture as luminance and alpha: its colour is the fur colour at the texel's height v
// (a linear function of v, root to tip) times a strand brightness, so a texel needs only L =
// brightness / kMaxStrandBrightness (1 / kMaxStrandBrightness where no strand is) and the
// alpha, and the colour at fin height v is min(1, (tint_root + tint_slope v) L) per channel,
// evaluated per fragment. Against `fin` (whose bytes hold the colour at the row's centre) it
// differs by L's rounding and by the colour's change within a row (at most a 256th of the
// root-to-tip difference at 256 rows). Sampled as raster::TexelFormat::La8.
struct FinLuminance {
  int size = 0;
  std::vector<uint8_t> la;  // size * size * 2 bytes: L, A
  glm::vec3 tint_root{0.0f}, tint_slope{0.0f};
};

struct StrandTextures {
  LayerTextures shells;  // params.shells layers of texture_size^2; rgba empty unless grown (ShellForms)
  ShellLuminance shell_luminance;  // the same shells as L, A and a tint per layer
  LayerTextures fin;     // 1 layer of texture_size^2 (none with fins off): strands seen from the side,
                         // u along the edge (repeat), v = row from root (0) to tip (1)
  FinLuminance fin_luminance;  // the same fin as L, A and a tint linear in v
  std::vector<ShellStrand> strands;  // in root-texel order (row-major)
};

// Fin strands per fin-texture column per unit density: a fin shows the strands within
// this many texels of depth behind the edge.
inline constexpr float kFinDepthTexels = 4.0f;

// Grows the textures for params (shells, texture_size, density, seed, root_color,
// tip_color). Exactly round(density/100 * size^2) distinct root texels (selection
// sampling). Colour at height h = mix(root_color, tip_color, h) * brightness. Fin: round(
// density/100 * size * kFinDepthTexels) strands, each a line from a random root column
// leaning by up to 0.1 * size over the fin height, length as for shells, alpha 1 - 0.8 v /
// length. Returns the first bad params field. Allocates: call once per fur block.
// Which forms of the shells to grow. The renderer samples only the luminance form; the RGBA
// form (4 bytes a texel: 16 layers of 256^2 are 4 MiB, of 1024^2 64 MiB) is for tests and
// tools that read the shells' colours directly. Every other output is the same either way.
enum class ShellForms : uint8_t { RgbaAndLuminance, LuminanceOnly };
std::optional<ParamError> generate_strand_textures(const FurParams& params, StrandTextures& out,
                                                   ShellForms forms = ShellForms::RgbaAndLuminance);

// The llvmpipe harness's textures, byte for byte (its README: 16 layers of 256^2 from
// mt19937 seed 2008, one 256^2 fin texture from seed 7600, colour (0.80,0.58,0.36)), and its
// shells' luminance form, whose colour is the harness's within L's rounding. `strands` is
// left empty (its strands are vertical columns).
StrandTextures match_llvmpipe_textures(ShellForms forms = ShellForms::RgbaAndLuminance);

}  // namespace pelt::fur
