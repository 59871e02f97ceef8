#include "tools/render/frame_stats.h"

#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace pelt::render {

namespace {
size_t stage_index(const char* name) {
  for (size_t i = 0; i < kStageCount; ++i)
    if (std::strcmp(kStageNames[i], name) == 0) return i;
  throw std::logic_error(std::string("unknown pipeline stage ") + name);
}
}  // namespace

StageRecord& FrameStats::stage(const char* name) { return stages[stage_index(name)]; }
const StageRecord& FrameStats::stage(const char* name) const { return stages[stage_index(name)]; }

nlohmann::json FrameStats::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (size_t i = 0; i < kStageCount; ++i)
    list.push_back({{"name", kStageNames[i]}, {"ran", stages[i].ran}, {"ms", stages[i].ms}});
  return {{"frame", frame},
          {"stages", list},
          {"samples", samples},
          {"triangles", triangles()},
          {"fragments", fragments()},
          {"raster",
           {{"triangles_culled", raster.triangles_culled},
            {"triangles_setup", raster.triangles_setup},
            {"bin_items", raster.bin_items},
            {"pixels_shaded", raster.pixels_shaded},
            {"fragments_blended", raster.fragments_blended},
            {"lanes_shaded", raster.lanes_shaded},
            // The exact sort: its translucent passes of tiles (more than the tiles where a pile of
            // layers is drawn in bands) and the most fragments one held; 0 under other sorts.
            {"exact_passes", raster.exact_passes},
            {"exact_fragments_peak", raster.exact_fragments_peak}}}};
}

}  // namespace pelt::render
