// Minimal servo loop against an installed inhap: render a flat heightmap with CBA.
#include <cstdio>

#include "inhap/geometry/heightmap.hpp"
#include "inhap/rendering/renderer.hpp"

int main() {
  inhap::Grid h(11, 11, 0.0), k(11, 11, 0.5);
  inhap::rendering::Model model(inhap::grid_to_mesh(h, 1.0, &k));
  inhap::rendering::State state;
  inhap::Vec3 f = inhap::Vec3::Zero();
  for (int i = 0; i <= 20; ++i)
    f = inhap::rendering::step(model, state, inhap::Vec3(5, 5, 1.0 - 0.1 * i),
                               inhap::rendering::Algorithm::kCBA);
  // 1 mm deep at 0.5 N/mm: 0.5 N up.
  std::printf("fz = %.3f N\n", f.z());
  return (f.z() > 0.49 && f.z() < 0.51) ? 0 : 1;
}
