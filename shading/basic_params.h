// Parameters of the basic materials (unlit, Lambert, Blinn-Phong), used by the renderer and by the
// paper's Lambert/Blinn comparison (Table 1).
#pragma once

#include <optional>

#include "shading/skin_params.h"

namespace pelt::shading {

struct BasicParams {
  float specular[3] = {0.3f, 0.3f, 0.3f};  // Blinn-Phong specular colour, each in [0, 100]
  float shininess = 32.0f;                 // Blinn-Phong exponent, in [1, 256]
};

std::optional<ParamError> validate(const BasicParams& p);

}  // namespace pelt::shading
