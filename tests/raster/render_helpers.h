// Small helpers shared by the raster tests: render with pelt into owned planes, and run
// a check once per compiled-in Highway target.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "raster/renderer.h"
#include "tests/hwy_targets.h"

namespace pelt::raster::test {

struct Image {
  int width = 0, height = 0;
  std::vector<float> color, depth;
  std::vector<uint32_t> id;
  RasterStats stats;
};

inline Image render(std::span<const DrawCall> draws, int w, int h, int threads = 1,
                    RenderOptions opt = {}) {
  Image img;
  img.width = w;
  img.height = h;
  img.color.assign(size_t(w) * h * 4, -1.0f);
  img.depth.assign(size_t(w) * h, -1.0f);
  img.id.assign(size_t(w) * h, 0xFFFFFFFFu);
  Renderer r(threads);
  RenderTarget t{w, h, img.color.data(), img.depth.data(), img.id.data()};
  r.render(draws, opt, t, &img.stats);
  return img;
}

using pelt::test::for_each_target;

}  // namespace pelt::raster::test
