#include "tests/fuzz/fuzz_entries.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <hwy/targets.h>

#include "fur/fur_geometry.h"
#include "raster/renderer.h"
#include "raster/texture.h"
#include "tests/tools/io/temp_dir.h"
#include "tools/io/input_error.h"
#include "tools/io/mesh_loader.h"
#include "tools/io/scene.h"

#ifndef PELT_REPO_DIR
#error "PELT_REPO_DIR must name the repository root (set by the CMake target)"
#endif

namespace pelt::fuzz {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InvariantViolation(what);
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite_matrix(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// The loaders read files, so each input is written to a per-process scratch file first.
std::filesystem::path write_scratch(const char* name, const uint8_t* data, size_t size) {
  const std::filesystem::path path = std::filesystem::path(scratch_dir()) / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) throw std::runtime_error("fuzz harness: cannot write " + path.string());
  return path;
}

// What load_mesh_file promises about a mesh it returns: validate_mesh passes (checked inside the
// loader) and every vertex has a finite normal.
void check_loaded(const io::LoadedMesh& loaded) {
  const Mesh& m = loaded.mesh;
  require(!m.indices.empty() && m.indices.size() % 3 == 0, "loaded mesh has no whole triangles");
  require(m.normals.size() == m.positions.size(), "loaded mesh lacks normals for some vertices");
  for (size_t i = 0; i < m.positions.size(); ++i) {
    if (!finite3(m.positions[i])) require(false, "loaded position " + std::to_string(i) + " is not finite");
    if (!finite3(m.normals[i])) require(false, "loaded normal " + std::to_string(i) + " is not finite");
  }
  for (uint32_t k : m.indices) require(k < m.positions.size(), "loaded index out of range");
  require(m.uvs.empty() || m.uvs.size() == m.positions.size(), "loaded uvs of the wrong length");
}

Outcome load_and_check(const std::filesystem::path& path) {
  try {
    check_loaded(io::load_mesh_file(path));
    return Outcome::accepted;
  } catch (const io::InputError&) {
    return Outcome::rejected;
  }
}

// Writes varyings 0..2 to rgb and checks the FragmentBatch contract on the way: every lane's
// varyings finite (uncovered lanes hold extrapolated planes, promised finite), covered lanes'
// depth in [0, 1]. Runs inline (Renderer(0)), so recording a failure in `failure` is safe.
class CheckingShader final : public raster::Shader {
 public:
  CheckingShader(float alpha, std::string* failure) : alpha_(alpha), failure_(failure) {}
  void shade(const raster::FragmentBatch& b) const override {
    for (uint32_t blk = 0; blk < b.blocks; ++blk) {
      for (int l = 0; l < raster::kBlockLanes; ++l) {
        const size_t i = size_t{blk} * raster::kBlockLanes + l;
        const bool covered = (b.mask[blk] >> l) & 1u;
        for (int k = 0; k < 3; ++k) {
          const float v = b.varying[k][i];
          if (!std::isfinite(v) && failure_->empty())
            *failure_ = "varying " + std::to_string(k) + " is not finite at lane " + std::to_string(i);
          b.out[k][i] = std::isfinite(v) ? v : 0.0f;
        }
        const float d = b.depth[i];
        if (covered && !(d >= 0.0f && d <= 1.0f) && failure_->empty())
          *failure_ = "fragment depth " + std::to_string(d) + " outside [0, 1]";
        b.out[3][i] = alpha_;
      }
    }
  }

 private:
  float alpha_;
  std::string* failure_;
};

}  // namespace

std::string scratch_dir() {
  // Removed at exit: every test and fuzzer process made one, and a CI machine kept them all.
  static const io::TempDir dir("pelt_fuzz_");
  return dir.path().string();
}

Outcome run_obj(const uint8_t* data, size_t size) {
  return load_and_check(write_scratch("input.obj", data, size));
}

Outcome run_fur(const uint8_t* data, size_t size) {
  io::LoadedMesh loaded;
  try {
    loaded = io::load_mesh_file(write_scratch("fur_input.obj", data, size));
  } catch (const io::InputError&) {
    return Outcome::rejected;
  }
  const Mesh& m = loaded.mesh;
  std::vector<fur::StrandCoordinates> mappings = {fur::StrandCoordinates::box, fur::StrandCoordinates::projected};
  if (!m.uvs.empty()) mappings.push_back(fur::StrandCoordinates::mesh);
  Outcome outcome = Outcome::rejected;
  for (const fur::StrandCoordinates mapping : mappings) {
    fur::FurParams params;
    params.shells = 4;
    params.texture_size = 16;
    params.texture_coordinates = mapping;
    fur::FurGeometry g;
    if (fur::build_fur_geometry(m, params, g)) continue;  // the fur refused the mesh, with its reason
    outcome = Outcome::accepted;
    const std::string in = std::string(" (") + std::string(fur::to_string(mapping)) + ")";
    const size_t n = g.base_vertex_count, total = g.positions.size();
    require(n == fur::fur_base_vertex_count(m, params), "the memory estimate's vertex count is not the build's" + in);
    require(total == n * g.layers && g.shell_uvs.size() == total && g.fin_uvs.size() == total,
            "fur arrays of the wrong length" + in);
    for (size_t i = 0; i < total; ++i) {
      require(finite3(g.positions[i]), "fur position " + std::to_string(i) + " is not finite" + in);
      require(std::isfinite(g.shell_uvs[i].x) && std::isfinite(g.shell_uvs[i].y) && std::isfinite(g.fin_uvs[i].x) &&
                  std::isfinite(g.fin_uvs[i].y),
              "fur uv " + std::to_string(i) + " is not finite" + in);
    }
    for (size_t i = 0; i < n; ++i)
      require(finite3(g.base_normals[i]) && std::abs(glm::length(g.base_normals[i]) - 1.0f) < 1e-3f,
              "fur normal " + std::to_string(i) + " is not a unit vector" + in);
    for (uint32_t k : g.shell_indices) require(k < total, "shell index out of range" + in);
    for (uint32_t k : g.fin_indices) require(k < total, "fin index out of range" + in);
    require(n >= m.positions.size() && g.counts.joined_vertices >= n - m.positions.size(),
            "box copies not joined to the vertex they copy" + in);
    for (size_t i = m.positions.size(); i < n; ++i) {
      const auto same = std::find(m.positions.begin(), m.positions.end(), g.positions[i]);
      require(same != m.positions.end(), "fur base vertex " + std::to_string(i) + " is no vertex of the mesh" + in);
    }
  }
  return outcome;
}

Outcome run_gltf(const uint8_t* data, size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  return load_and_check(write_scratch(glb ? "input.glb" : "input.gltf", data, size));
}

Outcome run_scene(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::filesystem::path anchor = std::filesystem::path(PELT_REPO_DIR) / "tools/scenes/fuzz_input.json";
  try {
    const io::Scene scene = io::parse_scene(text, anchor);
    require(!scene.objects.empty(), "accepted scene has no objects");
    const float aspect = float(scene.image.width) / float(scene.image.height);
    const int frames = scene.animation ? scene.animation->frames : 1;
    for (int frame : {0, frames - 1}) {
      const io::Camera cam = io::camera_at(scene, frame);
      require(finite3(cam.eye) && finite3(cam.target), "camera of frame " + std::to_string(frame) + " is not finite");
      require(finite_matrix(cam.view()), "accepted camera gives a non-finite view matrix");
      require(finite_matrix(cam.projection(aspect)), "accepted camera gives a non-finite projection");
    }
    return Outcome::accepted;
  } catch (const io::InputError&) {
    return Outcome::rejected;
  }
}

Outcome run_raster(const uint8_t* data, size_t size) {
  constexpr int kWidth = 72, kHeight = 40;  // two tiles wide, partial tiles and blocks
  static raster::Renderer renderer(0);
  uint8_t flags[2] = {0, 0};
  for (size_t k = 0; k < 2 && k < size; ++k) flags[k] = data[k];
  const size_t body = size > 2 ? size - 2 : 0;
  const size_t vertices = std::min(body / 12 / 3, kMaxFuzzTriangles) * 3;

  // At least one (unused) vertex, so an input too short for a triangle still submits a valid,
  // empty draw: the renderer rightly refuses null arrays, which is the caller's error, not a bug.
  std::vector<glm::vec3> positions(std::max<size_t>(vertices, 1), glm::vec3(0.0f));
  if (vertices > 0) std::memcpy(positions.data(), data + 2, vertices * sizeof(glm::vec3));
  std::vector<uint32_t> indices(std::max<size_t>(vertices, 3), 0u);
  std::vector<float> varyings(std::max<size_t>(vertices, 1) * 3, 0.0f);
  for (uint32_t i = 0; i < vertices; ++i) {
    // Reversed order on request, so the winding of every triangle flips.
    indices[i] = (flags[1] & 0x80) ? uint32_t(vertices - 1 - i) : i;
    varyings[size_t{i} * 3 + i % 3] = 1.0f;
  }

  raster::DrawCall draw;
  draw.positions = positions.data();
  draw.vertex_count = uint32_t(vertices);
  draw.indices = indices.data();
  draw.triangle_count = uint32_t(vertices / 3);
  draw.varyings = varyings.data();
  draw.varying_count = 3;
  draw.state.cull = raster::CullMode(flags[0] % 3);
  draw.state.blend = raster::BlendMode((flags[0] / 3) % 3);
  draw.state.depth_func = raster::DepthFunc((flags[0] / 9) % 3);
  draw.state.depth_write = (flags[0] / 27) % 2 == 0;
  // Identity: the floats are clip coordinates with w = 1. Perspective: w = -z, so w is zero,
  // negative, tiny or huge as the input pleases.
  if (flags[1] & 1)
    draw.clip_from_object = glm::perspective(glm::radians(60.0f), float(kWidth) / kHeight, 0.1f, 100.0f) *
                            glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -3.0f));
  std::string failure;
  const CheckingShader shader(draw.state.blend == raster::BlendMode::Opaque ? 1.0f : 0.5f, &failure);
  draw.shader = &shader;

  raster::RenderOptions options;
  options.sort = raster::SortMode((flags[1] >> 1) % 3);
  std::vector<float> color(size_t{kWidth} * kHeight * 4), depth(size_t{kWidth} * kHeight);
  std::vector<uint32_t> id(size_t{kWidth} * kHeight), overdraw(size_t{kWidth} * kHeight);
  raster::RenderTarget target{kWidth, kHeight, color.data(), depth.data(), id.data()};
  target.overdraw = overdraw.data();
  raster::RasterStats stats;
  renderer.render(std::span<const raster::DrawCall>(&draw, 1), options, target, &stats);

  require(failure.empty(), failure);
  // The overdraw AOV counts exactly the translucent fragments that passed the depth test.
  uint64_t counted = 0;
  for (uint32_t c : overdraw) counted += c;
  if (counted != stats.fragments_blended)
    require(false, "overdraw counts " + std::to_string(counted) + " fragments, the stats " +
                       std::to_string(stats.fragments_blended));
  require(draw.state.blend != raster::BlendMode::Opaque || counted == 0, "an opaque draw counted overdraw");
  // Messages are built only on failure: this loop runs for every pixel of every input.
  for (size_t p = 0; p < depth.size(); ++p) {
    if (!(depth[p] >= 0.0f && depth[p] <= 1.0f))
      require(false, "pixel " + std::to_string(p) + " depth " + std::to_string(depth[p]) + " outside [0, 1]");
    if (id[p] > draw.triangle_count)
      require(false, "pixel " + std::to_string(p) + " id " + std::to_string(id[p]) + " beyond the draw");
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(color[p * 4 + c])) require(false, "pixel " + std::to_string(p) + " colour is not finite");
  }
  return Outcome::accepted;
}

Outcome run_sampler(const uint8_t* data, size_t size) {
  uint8_t head[4] = {0, 0, 0, 0};
  for (size_t k = 0; k < 4 && k < size; ++k) head[k] = data[k];
  const size_t body = size > 4 ? size - 4 : 0;

  raster::SamplerState state;
  state.filter = raster::Filter(head[0] % 4);
  // An axis's wrap bit picks clamp or, with bit 6 of its size byte (which the sizes below barely
  // use), mirror: the decoding of inputs from before mirror existed is otherwise unchanged.
  const auto wrap = [](bool set, uint8_t size_byte) {
    return !set ? raster::Wrap::Repeat : (size_byte & 0x40) ? raster::Wrap::Mirror : raster::Wrap::Clamp;
  };
  state.wrap_u = wrap((head[0] & 0x04) != 0, head[1]);
  state.wrap_v = wrap((head[0] & 0x08) != 0, head[2]);
  const int format = (head[0] >> 4) % 3;  // RGBA8 linear, RGBA8 sRGB, La8
  const bool masked = (head[0] & 0x40) != 0;
  // Powers of two (the dense lanes' repeat needs them) or any size up to 64.
  const bool pow2 = (head[0] & 0x80) != 0;
  const int w = pow2 ? 1 << (head[1] % 9) : 1 + head[1] % 64;
  const int h = pow2 ? 1 << (head[2] % 9) : 1 + head[2] % 64;
  state.lod_bias = float(int8_t(head[3])) / 16.0f;

  // Texels from a fixed generator: the coordinates are what is fuzzed. A third of them fully
  // transparent and some opaque, as in the fur's strand textures.
  uint32_t x = 0x9E3779B9u ^ uint32_t(w * 977 + h);
  auto next = [&x] {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    return x;
  };
  const size_t texels = size_t(w) * size_t(h);
  const size_t channels = format == 2 ? 2 : 4;
  std::vector<uint8_t> bytes(texels * channels);
  for (size_t i = 0; i < texels; ++i) {
    const uint32_t r = next(), sel = r % 6;
    for (size_t c = 0; c + 1 < channels; ++c) bytes[i * channels + c] = uint8_t(r >> (8 * c + 3));
    bytes[i * channels + channels - 1] = sel < 2 ? 0 : sel == 2 ? 255 : uint8_t(r >> 24);
  }
  raster::Texture tex;
  const auto error = format == 2 ? raster::Texture::from_la8(w, h, bytes.data(), tex)
                                 : raster::Texture::from_rgba8(w, h, bytes.data(),
                                                               format == 1 ? raster::TexelEncoding::Srgb
                                                                           : raster::TexelEncoding::Linear,
                                                               tex);
  if (error) throw std::runtime_error("fuzz harness: texture " + error->message());

  // Lanes in whole blocks: the floats given, then zeros.
  const size_t given = std::min(body / 8, kMaxFuzzSampleBlocks * 16);
  const size_t lanes = std::max<size_t>((given + 15) / 16, 1) * 16;
  std::vector<float> u(lanes, 0.0f), v(lanes, 0.0f);
  for (size_t i = 0; i < given; ++i) {
    std::memcpy(&u[i], data + 4 + 8 * i, 4);
    std::memcpy(&v[i], data + 4 + 8 * i + 4, 4);
  }
  // A block's mask from its first lane's bits, with empty and full blocks among them.
  std::vector<uint16_t> mask(lanes / 16);
  for (size_t b = 0; b < mask.size(); ++b) {
    uint32_t bu, bv;
    std::memcpy(&bu, &u[16 * b], 4);
    std::memcpy(&bv, &v[16 * b], 4);
    const uint32_t m = bu ^ (bv >> 7) ^ uint32_t(b * 0x2545F491u);
    mask[b] = b % 5 == 0 ? uint16_t(0xFFFF) : b % 5 == 1 ? uint16_t(0) : uint16_t(m ^ (m >> 16));
  }

  std::vector<float> all[4], part[4];
  for (int c = 0; c < 4; ++c) {
    all[c].assign(lanes, -1.0f);
    part[c].assign(lanes, -1.0f);
  }
  float* const all_out[4] = {all[0].data(), all[1].data(), all[2].data(), all[3].data()};
  float* const part_out[4] = {part[0].data(), part[1].data(), part[2].data(), part[3].data()};
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    raster::sample(tex, state, u.data(), v.data(), lanes, all_out);
    if (masked) raster::sample(tex, state, u.data(), v.data(), lanes, part_out, mask.data());
    hwy::SetSupportedTargetsForTest(0);
    // Messages are built only on failure.
    for (size_t i = 0; i < lanes; ++i)
      for (int c = 0; c < 4; ++c) {
        const float a = all[c][i];
        if (!(a >= 0.0f && a <= 1.0f + 1e-6f))
          require(false, std::string(hwy::TargetName(target)) + " lane " + std::to_string(i) + " channel " +
                             std::to_string(c) + " sample " + std::to_string(a) + " outside [0, 1]");
        if (!masked) continue;
        const bool inside = (mask[i / 16] >> (i % 16)) & 1u;
        const float want = inside ? a : 0.0f;
        if (std::memcmp(&part[c][i], &want, sizeof(float)) != 0)
          require(false, std::string(hwy::TargetName(target)) + " lane " + std::to_string(i) + " channel " +
                             std::to_string(c) + ": masked " + std::to_string(part[c][i]) + ", unmasked " +
                             std::to_string(a) + (inside ? " inside" : " outside") + " the mask");
      }
  }
  return Outcome::accepted;
}

}  // namespace pelt::fuzz
