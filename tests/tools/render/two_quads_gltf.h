// A glTF of two textured quads for the render tests of glTF materials.
#pragma once

#include <cstdint>
#include <string>

#include "tests/tools/io/base64.h"

namespace pelt::render::test {

// Two quads facing +z, each its own primitive: at the back (z = -0.5) one of material 0, a
// plain opaque one without maps; in front (z = 0) one of material 1, `front` (a glTF material
// object), whose base colour texture is image 0, front.png. `back_uvs` false: the back quad's
// primitive has no TEXCOORD_0.
inline std::string two_quads_gltf(const std::string& front, bool back_uvs = true) {
  std::string bytes;
  const auto put = [&](const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); };
  for (const float z : {-0.5f, 0.0f}) {
    const float s = z < 0.0f ? 2.0f : 1.0f;  // the back quad larger, so it frames the front one
    const float pos[12] = {-s, -s, z, s, -s, z, s, s, z, -s, s, z};
    const float uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    put(pos, sizeof pos);
    put(uv, sizeof uv);
    put(idx, sizeof idx);
    bytes.append(4, '\0');  // 4-byte alignment of the next quad's floats
  }
  std::string views, accessors;
  for (int q = 0; q < 2; ++q) {
    const int base = q * 96;
    views += std::string(q ? "," : "") + R"({"buffer":0,"byteOffset":)" + std::to_string(base) +
             R"(,"byteLength":48},{"buffer":0,"byteOffset":)" + std::to_string(base + 48) +
             R"(,"byteLength":32},{"buffer":0,"byteOffset":)" + std::to_string(base + 80) + R"(,"byteLength":12})";
    accessors += std::string(q ? "," : "") + R"({"bufferView":)" + std::to_string(3 * q) +
                 R"(,"componentType":5126,"count":4,"type":"VEC3","min":[-2,-2,-0.5],"max":[2,2,0]},
                   {"bufferView":)" + std::to_string(3 * q + 1) + R"(,"componentType":5126,"count":4,"type":"VEC2"},
                   {"bufferView":)" + std::to_string(3 * q + 2) + R"(,"componentType":5123,"count":6,"type":"SCALAR"})";
  }
  const std::string back_attributes = back_uvs ? R"({"POSITION":0,"TEXCOORD_0":1})" : R"({"POSITION":0})";
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
  "meshes":[{"primitives":[{"attributes":)" + back_attributes + R"(,"indices":2,"material":0},
                           {"attributes":{"POSITION":3,"TEXCOORD_0":4},"indices":5,"material":1}]}],
  "materials":[{"name":"back"},)" + front + R"(],
  "textures":[{"source":0,"sampler":0}],"samplers":[{"magFilter":9728,"minFilter":9728}],"images":[{"uri":"front.png"}],
  "buffers":[{"byteLength":)" + std::to_string(bytes.size()) + R"(,"uri":"data:application/octet-stream;base64,)" +
         io::base64(bytes) + R"("}],
  "bufferViews":[)" + views + R"(],"accessors":[)" + accessors + "]}";
}

}  // namespace pelt::render::test
