#include <cstdio>
#include "bodies/patch_test.hpp"
using namespace ckpd;
int main() {
  auto r = run_patch_test(3, 3.015, 210e9, 0.3, PlaneMode::none);
  std::printf("3D N1 %u N2 %u N3 %u vol %.6f shear %.6f uni %.6f\n", r.n1, r.n2, r.n3, r.volumetric, r.shear, r.uniaxial);
  r = run_patch_test(2, 3.015, 210e9, 0.3, PlaneMode::stress);
  std::printf("2D N1 %u N2 %u N3 %u vol %.6f shear %.6f uni %.6f\n", r.n1, r.n2, r.n3, r.volumetric, r.shear, r.uniaxial);
}
