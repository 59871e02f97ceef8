// The entry points shared by the libFuzzer targets (tests/fuzz/fuzz_*.cpp) and the regression
// replay test (tests/tools/robust/fuzz_replay_test.cpp), so a crash input found by a fuzzer is
// replayed through exactly the same code in the normal build.
//
// Contract of every entry: bad input ends in io::InputError, which the entry catches and counts
// as a clean rejection. Anything else that escapes (another exception, or InvariantViolation
// thrown when an accepted input produced output that breaks a documented promise) is a bug; under
// libFuzzer it terminates the process and is reported as a crash.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace pelt::fuzz {

// An accepted input gave a result that breaks its interface's promise (a NaN normal from a
// loader, a depth outside [0, 1] from the rasterizer, ...).
struct InvariantViolation : std::logic_error {
  using std::logic_error::logic_error;
};

enum class Outcome { accepted, rejected };

// The bytes as a Wavefront OBJ file, through io::load_mesh_file.
Outcome run_obj(const uint8_t* data, size_t size);
// The bytes as a GLB file when they start with the "glTF" magic, else as a .gltf JSON file,
// through io::load_mesh_file.
Outcome run_gltf(const uint8_t* data, size_t size);
// The bytes as a Wavefront OBJ file, loaded as run_obj loads it, then grown into fur
// (fur::build_fur_geometry, 4 shells) under every strand mapping the mesh allows: "box",
// "projected", and "mesh" when it has uvs. Rejected when the loader refuses the file or the fur
// refuses the mesh (a ParamError). An accepted build must give finite positions, unit normals,
// finite shell and fin uvs and indices within its vertex array, as many base vertices as
// fur::fur_base_vertex_count (the memory estimate's count), and box copies that each sit on a
// vertex of the mesh and are joined to it.
Outcome run_fur(const uint8_t* data, size_t size);
// The bytes as scene JSON, through io::parse_scene anchored in tools/scenes/ (so the shipped
// scenes' relative mesh paths resolve), then camera_at on the first and last frame.
Outcome run_scene(const uint8_t* data, size_t size);
// The bytes as raw triangles: 2 bytes of pipeline state, then float32 x, y, z per vertex (NaN,
// Inf, denormal, huge: anything), at most kMaxFuzzTriangles triangles, one draw into a small
// target. Never rejected: every float pattern must render without NaN or out-of-range depth.
Outcome run_raster(const uint8_t* data, size_t size);

// The bytes as a texture sampling call: 4 bytes of sampler state and texture shape (filter,
// wraps, format RGBA8 / sRGB / La8, a block mask or none, width and height from 1 to 64 or a power
// of two up to 256, LOD bias), then float32 u, v per lane (NaN, Inf, huge: anything), at most
// kMaxFuzzSampleBlocks blocks of 16, sampled by raster::sample on every compiled Highway target.
// Never rejected: every sample must be finite and within [0, 1], the masked call must give the
// unmasked call's samples inside its mask and +0 outside, and nothing may read outside the
// texture (AddressSanitizer in the fuzz build).
Outcome run_sampler(const uint8_t* data, size_t size);

inline constexpr size_t kMaxFuzzTriangles = 300;
inline constexpr size_t kMaxFuzzSampleBlocks = 160;  // two and a half of the sampler's 64-block chunks

// Where the temporary input files of run_obj / run_gltf live (one folder per process).
std::string scratch_dir();

}  // namespace pelt::fuzz
