// The fields of a scene object's `fur` block, with their defaults and accepted ranges.
// The scene parser fills a FurParams from JSON (keys = the member names below, nested
// blocks as JSON objects) and calls validate(); everything in fur/ assumes a FurParams
// that validate() accepted.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pelt::fur {

// Which fins are drawn. `off`: none. `all`: every edge's fin at full opacity (the
// llvmpipe harness). `silhouette`: fins faded in near silhouettes by fin_weight()
// (Lengyel et al. 2001), where shells alone show gaps.
enum class FinMode { off, all, silhouette };

// Gravity (seed eq. 2). The block is optional: without it no gravity pass runs.
struct GravityParams {
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // "direction": length > 1e-6; normalised
  float strength = 1.0f;                   // "strength": >= 0, <= 1e3; 0 = no bend
  float stability = 200.0f;                // "stability": > 0, <= 1e9; larger = stiffer
};

// Wind (seed 3.2.2). Optional: without it no wind field is built.
struct WindParams {
  glm::vec3 direction{1.0f, 0.0f, 0.0f};  // "direction": length > 1e-6; normalised
  float strength = 1.0f;                  // "strength": >= 0, <= 1e3 (force magnitude)
  float gust_frequency = 0.5f;            // "gust_frequency": gusts per second, >= 0, <= 1e3
  float gust_scale = 0.5f;                // "gust_scale": in [0, 1]; 0 = steady wind
};

// Where the comb direction d comes from.
enum class CombField {
  uniform,  // one direction for the whole mesh ("direction")
  uv,       // per vertex, from the mesh: the surface direction along which the texture
            // coordinates move as "uv_direction" says, so fur follows the UV layout an
            // artist laid out (e.g. [0, 1]: toward growing v, down the head in glTF's v)
};

// Combing (seed Fig. 6): growth direction g = normalize((1 - weight) n + weight d).
// Optional: without it g is the vertex normal n. Where the blend cancels (d = -n at
// weight 0.5) the normal is used. A blend lower than kMinFurElevation above the tangent
// plane (fur/fur_geometry.h) is raised to it: a comb lays fur down, never into the mesh
// (d = -n above weight 0.5 keeps the normal).
struct CombParams {
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // "direction": length > 1e-6; normalised
  float weight = 0.5f;                     // "weight": in [0, 1]; 0 = plain normals
  CombField field = CombField::uniform;    // "field": "uniform" | "uv"
  // "uv_direction": field "uv" only: [du, dv], length > 1e-6. A vertex's d is
  // du T_u + dv T_v, with T_u, T_v its surface derivatives of position with respect to
  // u and v (the area-weighted sum over its triangles, projected onto its tangent plane),
  // normalised; the copies of a split seam's vertex take their joined direction. Where the
  // mesh's uvs give no direction (degenerate uv triangles, or copies at one position combing
  // different ways, as at a UV sphere's pole), the vertex keeps its normal.
  glm::vec2 uv_direction{1.0f, 0.0f};
};

// Where the shells' strand texture lies on the mesh.
enum class StrandCoordinates {
  mesh,       // the mesh's texture coordinates, scaled to pelt's strand scale (below)
  projected,  // a planar projection along the body diagonal (the llvmpipe harness's mapping)
  box,        // each triangle projected on the axis plane it faces most (a cube projection)
};

struct FurParams {
  // "shells": number of layers S including layer 0 on the base surface; in [2, 128].
  int shells = 16;
  // Not a JSON key: the shell count the fur is authored for, set when a quality setting
  // re-slices the same fur into `shells` layers (0: `shells` itself). Two things are defined
  // per layer and are rescaled so that the fur, not its slicing, stays the same:
  // - opacity: each layer's strand alpha a becomes 1 - (1 - a)^((authored_shells - 1) /
  //   (shells - 1)), so the optical depth per unit of fur height stays the same as the layer
  //   count changes (Beer-Lambert over the layer spacing): more shells converge to the volume
  //   the authored count samples, instead of stacking ever more opaque layers;
  // - gravity: eq. 2 bends a chain by theta per node with RN nodes remaining, so its total
  //   bend grows with the square of the node count; apply_gravity scales theta to keep the
  //   authored chain's total bend (fur/dynamics.h).
  // 0 or [2, 128].
  int authored_shells = 0;
  // "length": distance of the outermost layer from the base surface, as a FRACTION OF
  // THE BASE MESH'S BOUNDING RADIUS R (largest distance of a vertex from the
  // bounding-box centre), so a scene keeps its look when a mesh is rescaled. In
  // (0, 2]. Layer spacing SL_D = length * R / (shells - 1). Default 0.1 = the FPS
  // tables' setting.
  float length = 0.1f;
  // "density": strand roots per 100 texels of the base-level shell texture, i.e. the
  // percentage of layer-0 texels where a strand starts (the seed's "density 15 / 30"
  // read as 15% / 30%; the llvmpipe harness uses 30). Exactly
  // round(density/100 * texture_size^2) distinct root texels are chosen. In (0, 100].
  float density = 30.0f;
  // "texture_size": side of each square layer texture in texels; a power of two in
  // [16, 4096].
  int texture_size = 256;
  // "texture_coordinates": "mesh" | "box" | "projected"; unset: "mesh" when the mesh has texture
  // coordinates, "box" when it has none. "projected" is the llvmpipe harness's mapping: k (p -
  // centre).e1, .e2 with k = 2.449490 sqrt(3) / R along the body diagonal (4 repeats along each
  // edge of its box); it stretches strands without bound where the surface runs along the
  // diagonal (a band around a sphere). "box" projects each triangle on the axis plane it faces
  // most (x, y or z, by its corners' fur normals, or by its own normal where theirs would leave it
  // facing that plane by less than a half), which stretches a strand at most twice (sqrt(3) times
  // on a smooth surface), copying the vertices where the planes meet (fur/fur_geometry.cpp,
  // split_by_facing_axis).
  // Whatever the mapping, the strand texture is laid at one scale, so a strand is as wide on a
  // uv-mapped mesh as on the same mesh without uvs, whatever its UV layout: the mesh's uvs and the
  // box's planes are multiplied by sqrt(A_p / A), A their area in the texture and A_p the texture
  // area the projection lays on the same mesh, at least a quarter of the mesh's area at k (a
  // factor within 0.1 % of 1 is 1: the built-in box's and teapot's uvs are that projection). A
  // layout spanning [0, 1] once over a whole character, as an atlas does, would otherwise make
  // each strand a patch of its surface.
  std::optional<StrandCoordinates> texture_coordinates;
  // Uvs that cover no area (all at a point) are an error under an explicit "mesh"; unset, the strands
  // are laid by "box" and the user is warned.
  // "texture_repeat": the strand texture repeats this many times as often as at that scale
  // (finer strands above 1, coarser below), the fins' strands along an edge too; in (0, 1000].
  float texture_repeat = 1.0f;
  // "seed": seeds the strand generators (std::mt19937); the same seed gives the same
  // textures. Any value in [0, 2^32 - 1].
  uint32_t seed = 1;
  // "fins": "off" | "all" | "silhouette".
  FinMode fins = FinMode::silhouette;
  // "root_color", "tip_color": linear RGB, each component in [0, 1]; strand colour
  // runs from root to tip.
  glm::vec3 root_color{0.36f, 0.261f, 0.162f};
  glm::vec3 tip_color{0.80f, 0.58f, 0.36f};
  // "use_color_map": the strands also take the colour of the object's colour map under them
  // (a pelt addition; the seed's fur has one colour): colour = the root-to-tip colour x the map
  // at the base mesh's texture coordinate, per fragment (tools/render/fur_shader.h). Needs a
  // mesh with uvs (FurGeometry::mesh_uvs); which map is the renderer's business.
  bool use_color_map = false;
  std::optional<GravityParams> gravity;  // "gravity": {direction, strength, stability}
  std::optional<WindParams> wind;        // "wind": {direction, strength, gust_frequency, gust_scale}
  std::optional<CombParams> comb;        // "comb": {direction, weight}
};

// A rejected field: its JSON key path inside the fur block (e.g. "gravity.stability",
// "root_color[2]") and why.
struct ParamError {
  std::string field;
  std::string reason;
};

// The first bad field, or nothing when every field is in range (NaN and infinities are
// rejected everywhere).
std::optional<ParamError> validate(const FurParams& params);

std::string_view to_string(FinMode mode);
std::string_view to_string(StrandCoordinates coordinates);
// What a texture_coordinates value must be, in the words of every error that refuses one.
inline constexpr const char* kStrandCoordinatesChoice = "must be \"mesh\", \"box\" or \"projected\"";
// "mesh" | "projected" | "box" (exact, lower case); nothing for any other text.
std::optional<StrandCoordinates> strand_coordinates_from_string(std::string_view text);
// "off" | "all" | "silhouette" (exact, lower case); nothing for any other text.
std::optional<FinMode> fin_mode_from_string(std::string_view text);

}  // namespace pelt::fur
