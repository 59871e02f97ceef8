// Varying layout of the draws the scene renderer builds: what the rasterizer interpolates
// per fragment, by slot. Material draws and fur draws each have their own layout.
#pragma once

namespace pelt::render {

// Opaque surfaces (lambert, blinn, unlit, skin).
struct SurfaceVaryings {
  static constexpr int kPos = 0;      // world position, 3
  static constexpr int kNormal = 3;   // world normal, 3
  static constexpr int kUv = 6;       // texture coordinate, 2
  static constexpr int kCount = 8;
  // Without maps nothing reads the uv: the draw ends before it, so the rasterizer does not
  // interpolate it (a quarter of the interpolation work of a dense untextured mesh).
  static constexpr int kCountWithoutUv = 6;
  static constexpr int kBlurred = 8;  // normal_blur only: blurred normals r, g, b (3 x 3)
  static constexpr int kCountBlurred = 17;
};

// Fur shells and fins, lit per vertex (the default): the strand lighting is smooth across
// a shell, so it is evaluated once per fur vertex and only the texture varies per pixel.
struct FurVaryings {
  static constexpr int kUv = 0;        // shell uv (shells) or fin uv (fins), 2
  static constexpr int kDiffuse = 2;   // light that multiplies the strand colour, 3
  static constexpr int kSpecular = 5;  // light added on top, 3
  static constexpr int kCount = 8;
};

// FurVaryings when every fur vertex's light is grey (equal in r, g and b, as under white
// lights): one diffuse and one specular value stand for three, so the rasterizer
// interpolates half the varyings.
struct FurGreyVaryings {
  static constexpr int kUv = 0;        // 2
  static constexpr int kDiffuse = 2;   // 1
  static constexpr int kSpecular = 3;  // 1
  static constexpr int kCount = 4;
};

// With the fur's use_color_map, every fur layout above and below gains the mesh's own texture
// coordinate (2 floats, where the colour map is read) after its kCount.
struct FurMapUv {
  static constexpr int kCount = 2;
};

// Fur lit per pixel (Kajiya-Kay evaluated per fragment).
struct FurPixelVaryings {
  static constexpr int kPos = 0;      // world position of the deformed fur vertex, 3
  static constexpr int kTangent = 3;  // strand tangent from the deformed chain, 3
  static constexpr int kUv = 6;       // shell uv (shells) or fin uv (fins), 2
  static constexpr int kHeight = 8;   // layer / (shells - 1): 0 at the root, 1 at the tip
  static constexpr int kNormal = 9;   // base surface normal, 3
  static constexpr int kCount = 12;
};

}  // namespace pelt::render
