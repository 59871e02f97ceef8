// Shaders for raster tests: they know only the FragmentBatch contract.
#pragma once

#include <algorithm>
#include <glm/vec4.hpp>

#include "raster/pipeline.h"

namespace pelt::raster::test {

// Writes one colour to every lane.
class ConstantShader final : public Shader {
 public:
  explicit ConstantShader(glm::vec4 c) : c_(c) {}
  void shade(const FragmentBatch& b) const override {
    const size_t lanes = size_t{b.blocks} * kBlockLanes;
    for (int k = 0; k < 4; ++k) std::fill(b.out[k], b.out[k] + lanes, c_[k]);
  }

 private:
  glm::vec4 c_;
};

// Copies varyings 0..2 to r, g, b (absent ones read 0) and writes alpha.
class VaryingShader final : public Shader {
 public:
  explicit VaryingShader(float alpha = 1.0f, bool derivatives = false)
      : alpha_(alpha), derivatives_(derivatives) {}
  bool uses_derivatives() const override { return derivatives_; }
  void shade(const FragmentBatch& b) const override {
    const size_t lanes = size_t{b.blocks} * kBlockLanes;
    for (int k = 0; k < 3; ++k)
      for (size_t i = 0; i < lanes; ++i) b.out[k][i] = b.varying[k] ? b.varying[k][i] : 0.0f;
    std::fill(b.out[3], b.out[3] + lanes, alpha_);
  }

 private:
  float alpha_;
  bool derivatives_;
};

}  // namespace pelt::raster::test
