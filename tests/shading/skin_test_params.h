// Test helper: skin parameters with every layer off, so that a test turns on the term it checks.
#pragma once

#include "shading/skin_params.h"

namespace pelt::shading::testing {

// Every layer switched off, white, unit coefficients.
inline SkinParams bare_skin() {
  SkinParams p;
  p.single_scattering = SingleScattering::off;
  p.multiple_scattering = MultipleScattering::off;
  p.AmbientCoeff = 0.0f;
  p.Specularity = 0.0f;
  p.SingleScatteringCoeff = 1.0f;
  p.MultipleScatteringCoeff = 1.0f;
  for (int c = 0; c < 3; ++c) p.SkinColor[c] = p.DiffusionColor[c] = p.SheenColor[c] = 1.0f;
  return p;
}

}  // namespace pelt::shading::testing
