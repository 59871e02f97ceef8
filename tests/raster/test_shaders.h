// Shaders for raster tests: they know only the FragmentBatch contract.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

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

// A colour per triangle: r, g, b from a hash of (seed, primitive), alpha one of `alphas` by the
// same hash (values outside [0, 1] and NaN included, as a shader may write them).
class PrimitiveShader final : public Shader {
 public:
  PrimitiveShader(uint32_t seed, std::vector<float> alphas, bool derivatives = false)
      : seed_(seed), alphas_(std::move(alphas)), derivatives_(derivatives) {}
  bool uses_derivatives() const override { return derivatives_; }
  glm::vec4 colour(uint32_t primitive) const {
    uint32_t h = (primitive + 1) * 0x9E3779B1u ^ seed_;
    h ^= h >> 15;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    return {float(h & 255u) / 255.0f, float((h >> 8) & 255u) / 255.0f, float((h >> 16) & 255u) / 255.0f,
            alphas_[(h >> 24) % alphas_.size()]};
  }
  void shade(const FragmentBatch& b) const override {
    for (size_t i = 0; i < size_t{b.blocks} * kBlockLanes; ++i) {
      const glm::vec4 c = colour(b.primitive[i]);
      for (int k = 0; k < 4; ++k) b.out[k][i] = c[k];
    }
  }

 private:
  uint32_t seed_;
  std::vector<float> alphas_;
  bool derivatives_;
};

}  // namespace pelt::raster::test
