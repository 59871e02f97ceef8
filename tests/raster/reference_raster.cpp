#include "tests/raster/reference_raster.h"

#include <algorithm>

#include "raster/clip.h"
#include "raster/config.h"
#include "raster/setup.h"

namespace pelt::raster::test {

bool reference_covers(const int32_t x[3], const int32_t y[3], int32_t px, int32_t py) {
  const int64_t cx = int64_t{px} * 256 + 128, cy = int64_t{py} * 256 + 128;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const int64_t ex = int64_t{x[j]} - x[i], ey = int64_t{y[j]} - y[i];
    const int64_t e = ex * (cy - y[i]) - ey * (cx - x[i]);
    if (e > 0) continue;
    if (e < 0) return false;
    // On the edge: owned only by a top edge (horizontal, interior below, i.e. walking
    // towards +x in y-down space with positive orientation) or a left edge (interior to
    // the right: walking towards -y).
    const bool top = ey == 0 && ex > 0;
    const bool left = ey < 0;
    if (!(top || left)) return false;
  }
  return true;
}

ReferenceImage reference_render(std::span<const DrawCall> draws, int width, int height, bool record_fragments,
                                const ReferenceAlpha& alpha) {
  ReferenceImage img;
  img.width = width;
  img.height = height;
  img.depth.assign(size_t(width) * height, kClearDepth);
  img.id.assign(size_t(width) * height, 0);
  img.count.assign(size_t(width) * height, 0);
  if (record_fragments) img.fragments.resize(size_t(width) * height);
  const Viewport vp{width, height};
  const ClipBounds bounds = make_clip_bounds(width, height);
  for (size_t pass = 0; pass < 2 * draws.size(); ++pass) {
    const size_t draw = pass % draws.size();
    const DrawCall& d = draws[draw];
    if (d.state.alpha_test != (pass >= draws.size())) continue;  // alpha-tested draws second
    for (uint32_t p = 0; p < d.triangle_count; ++p) {
      glm::vec4 c[3];
      bool bad = false;
      for (int k = 0; k < 3; ++k) {
        const uint32_t i = d.indices[3 * p + k];
        if (i >= d.vertex_count) bad = true;
        else c[k] = d.clip_from_object * glm::vec4(d.positions[i], 1.0f);
      }
      if (bad) continue;
      ClipPolygon poly;
      if (clip_triangle(c[0], c[1], c[2], bounds, poly) == ClipResult::Culled) continue;
      for (int f = 1; f + 1 < poly.count; ++f) {
        const ClipVertex* v[3] = {&poly.v[0], &poly.v[f], &poly.v[f + 1]};
        SnappedVertex s[3];
        for (int k = 0; k < 3; ++k) s[k] = snap_vertex(*v[k], vp);
        int32_t x[3] = {s[0].x, s[1].x, s[2].x}, y[3] = {s[0].y, s[1].y, s[2].y};
        const int64_t area = (int64_t{x[1]} - x[0]) * (int64_t{y[2]} - y[0]) -
                             (int64_t{y[1]} - y[0]) * (int64_t{x[2]} - x[0]);
        if (area == 0) continue;
        const bool front = area < 0;  // counter-clockwise in NDC
        if ((d.state.cull == CullMode::Back && !front) || (d.state.cull == CullMode::Front && front))
          continue;
        if (area < 0) {
          std::swap(x[1], x[2]);
          std::swap(y[1], y[2]);
        }
        TriSetup setup;
        const bool has_setup = setup_triangle(*v[0], *v[1], *v[2], vp, d.state.cull, setup);
        // A conservative pixel range from the snapped extent (one pixel of slack).
        const int32_t x0 = std::max(0, std::min({x[0], x[1], x[2]}) / 256 - 1);
        const int32_t x1 = std::min(width - 1, std::max({x[0], x[1], x[2]}) / 256 + 1);
        const int32_t y0 = std::max(0, std::min({y[0], y[1], y[2]}) / 256 - 1);
        const int32_t y1 = std::min(height - 1, std::max({y[0], y[1], y[2]}) / 256 + 1);
        for (int py = y0; py <= y1; ++py)
          for (int px = x0; px <= x1; ++px) {
            if (!reference_covers(x, y, px, py)) continue;
            if (!has_setup) {
              // set-up must never drop a triangle that covers a pixel; flag it loudly.
              img.count[size_t(py) * width + px] = 0xDEADu;
              continue;
            }
            if (d.state.alpha_test && !(alpha(uint32_t(draw), p, px, py) >= d.state.alpha_cutoff)) continue;
            const float z = eval_depth(setup, px, py);
            float& zb = img.depth[size_t(py) * width + px];
            const bool pass = d.state.depth_func == DepthFunc::Always ? true
                              : d.state.depth_func == DepthFunc::Less ? z < zb
                                                                      : z <= zb;
            if (!pass) continue;
            ++img.count[size_t(py) * width + px];
            if (record_fragments) img.fragments[size_t(py) * width + px].push_back({uint32_t(draw), p, z});
            if (d.state.depth_write) {
              zb = z;
              img.id[size_t(py) * width + px] = d.id_base + p + 1;
            }
          }
      }
    }
  }
  for (float& z : img.depth) z = std::min(z, 1.0f);  // the clear reads 1, as the renderer resolves it
  return img;
}

}  // namespace pelt::raster::test
