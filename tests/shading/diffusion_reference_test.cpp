#include "shading/diffusion_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shading/skin_reference.h"

namespace pelt::shading::diffusion {
namespace diffusion_reference_test {  // named, not anonymous: the unity build compiles files together (tests/CMakeLists.txt)

constexpr double kPi = 3.14159265358979323846;

Medium with_albedo(double alpha, double eta, double sigma_t = 1.0) {
  return Medium{(1.0 - alpha) * sigma_t, alpha * sigma_t, eta};
}

TEST(DiffusionReference, ProfileIntegratesToTheClosedFormTotal) {
  for (double alpha : {0.3, 0.6, 0.9, 0.99})
    for (double eta : {1.0, 1.3, 1.4, 2.0}) {
      const Medium m = with_albedo(alpha, eta, 2.0);
      const double str = std::sqrt(3.0 * m.sigma_a * (m.sigma_a + m.sigma_s_prime));
      // r = e^t, dr = r dt: integral of 2 pi r^2 R_d(r) dt, composite Simpson.
      const double t0 = std::log(1e-7), t1 = std::log(80.0 / str + 20.0);
      const int n = 40000;
      const double h = (t1 - t0) / n;
      auto f = [&](double t) {
        const double r = std::exp(t);
        return 2.0 * kPi * r * r * profile(r, m);
      };
      double sum = f(t0) + f(t1);
      for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(t0 + i * h);
      const double numeric = sum * h / 3.0;
      const double closed = total_reflectance(alpha, eta);
      EXPECT_NEAR(numeric, closed, 1e-3 * closed) << "alpha " << alpha << " eta " << eta;
    }
}

TEST(DiffusionReference, ClosedFormIsPublishedValueAndMatchesShaderTerm) {
  // alpha' = 1: no absorption, everything comes back out.
  EXPECT_NEAR(total_reflectance(1.0, 1.3), 1.0, 1e-15);
  // Independent evaluation of the published formula at alpha' = 0.8, eta = 1.3.
  const double fdr = -1.440 / (1.3 * 1.3) + 0.710 / 1.3 + 0.668 + 0.0636 * 1.3;
  const double A = (1 + fdr) / (1 - fdr);
  const double s = std::sqrt(3.0 * 0.2);
  EXPECT_NEAR(total_reflectance(0.8, 1.3), 0.4 * (1 + std::exp(-4.0 / 3.0 * A * s)) * std::exp(-s), 1e-15);
  EXPECT_EQ(total_reflectance(0.8, 1.3), ref::dipole_total_rd(0.8, 1.3));
}

TEST(DiffusionReference, UniformlyLitLargePlaneGivesTotalReflectanceTimesIrradiance) {
  for (double alpha : {0.5, 0.9}) {
    const Medium m = with_albedo(alpha, 1.4);
    const double str = std::sqrt(3.0 * m.sigma_a * (m.sigma_a + m.sigma_s_prime));
    const double extent = 18.0 / str;
    const double h = 0.05;
    const int n = int(2 * extent / h);
    std::vector<float> pos, area, irr;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // Cell centres, the shaded point at a cell centre.
        pos.insert(pos.end(), {float((i - n / 2) * h), float((j - n / 2) * h), 0.0f});
        area.push_back(float(h * h));
        irr.push_back(2.5f);
      }
    const double point[3] = {0, 0, 0};
    const double M = exitance(m, point, pos.data(), area.data(), irr.data(), area.size());
    const double expect = total_reflectance(alpha, 1.4) * 2.5;
    EXPECT_NEAR(M, expect, 1e-3 * expect) << "alpha " << alpha;
  }
}

TEST(DiffusionReference, ExitanceIsLinearAndLocal) {
  const Medium m = with_albedo(0.8, 1.4);
  const float pos[6] = {0, 0, 0, 3, 0, 0};
  const float area[2] = {0.01f, 0.01f};
  const float e1[2] = {1, 0}, e2[2] = {2, 0}, e3[2] = {0, 1};
  const double p[3] = {0, 0, 0};
  EXPECT_NEAR(exitance(m, p, pos, area, e2, 2), 2 * exitance(m, p, pos, area, e1, 2), 1e-15);
  EXPECT_LT(exitance(m, p, pos, area, e3, 2), exitance(m, p, pos, area, e1, 2)) << "light far away contributes less";
  EXPECT_NEAR(exitance(m, p, pos, area, e1, 2), profile(0.0, m) * 0.01f, 1e-15);
}

TEST(DiffusionReference, ValidateNamesTheField) {
  auto e = validate(Medium{0.0, 1.0, 1.4});
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "sigma_a");
  e = validate(Medium{0.1, 1.0, 9.0});
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "eta");
  EXPECT_FALSE(validate(Medium{0.1, 1.0, 1.4}).has_value());
}

}  // namespace diffusion_reference_test
}  // namespace pelt::shading::diffusion
