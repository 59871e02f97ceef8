// Per-frame proof of what was computed: every pipeline stage, whether it ran, and its
// time; triangle and fragment counts. Written by `pelt render --stats`.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "raster/renderer.h"

namespace pelt::render {

// The stage names, in pipeline order (documented in the README). A frame lists every one
// of them, ran or skipped.
inline constexpr const char* kStageNames[] = {
    "meshes",        // load and validate mesh files, bake transforms (first frame only)
    "textures",      // colour and normal maps: read, decoded, mip chains (once per mapped object)
    "fur_geometry",  // shared shell/fin vertex array of eq. 1 (once per furry object)
    "fur_textures",  // strand textures and their mip chains (once per furry object)
    "normal_blur",   // blurred normals for normal_blur skin (once per such mesh)
    "gravity",       // the gravity pose (when its inputs change)
    "wind",          // the wind field and wind pose (in frames where the wind changes)
    "fur_pose",      // lerp of the two poses, strand tangents, fur varyings
    "fur_lighting",  // strand lighting per fur vertex (when pose, view or lights change)
    "fins",          // view-dependent fin weights and the list of visible fins
    "fur_sort",      // the surface sort's keys (sort surface only; when the pose or camera moves)
    "raster_front",  // transform, clip, set-up, binning
    "raster_tiles",  // rasterize, shade, blend, resolve
    "write",         // image output
};
inline constexpr size_t kStageCount = sizeof(kStageNames) / sizeof(kStageNames[0]);

struct StageRecord {
  bool ran = false;
  double ms = 0.0;
};

struct FrameStats {
  int frame = 0;
  StageRecord stages[kStageCount];
  int samples = 1;         // rasterizer passes: the quality's samples per pixel
  raster::RasterStats raster;  // the rasterizer's counters and times, summed over the passes

  uint64_t triangles() const { return raster.triangles_submitted; }
  // Visible opaque plus blended translucent fragments.
  uint64_t fragments() const { return raster.fragments_visible + raster.fragments_blended; }

  StageRecord& stage(const char* name);
  const StageRecord& stage(const char* name) const;
  nlohmann::json to_json() const;
};

// Times one stage and marks it as ran; a stage never constructed stays skipped.
class StageTimer {
 public:
  StageTimer(FrameStats& stats, const char* name)
      : record_(stats.stage(name)), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    record_.ran = true;
    record_.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StageRecord& record_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pelt::render
