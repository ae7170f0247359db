// Samples pressing on a surface with relief, as a rig's force-controlled exploration records
// them (a known answer for the estimated surface): the probe-centre surface z = A sin(w x)
// sin(w y) over 40 x 40 mm (w = 2 pi / wavelength), a linear law (1 N/mm: depth = f_n), each
// sample at a random place pressed along the local normal. A share `light_share` of the samples
// press with exactly `light_n`; the others with 0.2-2.5 N (or, for light_share 0, 1.5-2.5 N).
// Units: mm, N, s (66 Hz time stamps).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include "inhap/core/csv.hpp"

namespace inhap::test {

struct ReliefRecording {
  double amplitude = 1.0, wavelength = 8.0;  ///< mm
  double light_share = 0.8, light_n = 0.2;
  int samples = 6000;
  std::uint64_t seed = 777;

  /// The probe-centre surface's height at (x, y), mm.
  double height(double x, double y) const {
    const double w = 2 * std::numbers::pi / wavelength;
    return amplitude * std::sin(w * x) * std::sin(w * y);
  }

  Recording record() const {
    Recording rec;
    std::uint64_t state = seed;
    const auto uniform = [&state] {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return double(state >> 11) / double(1ULL << 53);
    };
    const double w = 2 * std::numbers::pi / wavelength;
    for (int i = 0; i < samples; ++i) {
      const double x = 40 * uniform(), y = 40 * uniform();
      const Vec3 on(x, y, height(x, y));
      const Vec3 n = Vec3(-amplitude * w * std::cos(w * x) * std::sin(w * y),
                          -amplitude * w * std::sin(w * x) * std::cos(w * y), 1.0)
                         .normalized();
      const double u = uniform();
      const double f =
          u < light_share ? light_n : (light_share > 0 ? 0.2 + 2.3 * uniform() : 1.5 + uniform());
      rec.t.push_back(i / 66.0);
      rec.p.push_back(on - f * n);  // depth = f / (1 N/mm)
      rec.f.push_back(f * n);
    }
    return rec;
  }
};

}  // namespace inhap::test
