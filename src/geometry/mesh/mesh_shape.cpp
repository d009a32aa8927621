#include "src/geometry/mesh/mesh_shape.hpp"

#include <cmath>

namespace ckpd {

MeshShape::MeshShape(LoadedMesh loaded, InsideTest test)
    : mesh_(loaded.mesh), info_(loaded.info), inside_(loaded.mesh, test) {
  const Vec3 extent = info_.hi - info_.lo;
  estimate_volume_ = info_.closed ? info_.mesh_volume : extent.prod();
}

LatticeSample MeshShape::sample(double dx, double horizon, std::size_t max_points) const {
  return inside_.sample(dx, horizon, max_points, estimate_volume_ / (dx * dx * dx));
}

namespace {

const bool mesh_registered = register_shape("mesh", [](const CaseNode& n, int dim) {
  if (dim != 3) n.fail("a 3D body for a mesh geometry");
  InsideTest test = InsideTest::strict;
  if (auto t = n.optional("inside_test")) {
    const std::string s = t->as_string();
    if (s != "strict" && s != "tolerant") t->fail("'strict' (closed surfaces) or 'tolerant'");
    test = s == "tolerant" ? InsideTest::tolerant : InsideTest::strict;
  }
  LoadedMesh loaded = load_mesh(n, test == InsideTest::tolerant);
  return std::unique_ptr<Shape>(new MeshShape(std::move(loaded), test));
});

}  // namespace

}  // namespace ckpd
