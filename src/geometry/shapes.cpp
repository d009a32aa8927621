// The built-in shapes. Points on a shape's surface count as inside (with a relative tolerance
// of 1e-12 of the shape's size), so lattice points that sit exactly on a face are kept.
#include <cmath>
#include <limits>

#include "src/geometry/shape.hpp"

namespace ckpd {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kSurfaceTolerance = 1e-12;

class Box : public Shape {
 public:
  Box(Vec3 lo, Vec3 hi, int dimension) : lo_(lo), hi_(hi), dimension_(dimension) {}
  bool contains(const Vec3& p) const override {
    const double tol = kSurfaceTolerance * (hi_ - lo_).norm();
    for (int d = 0; d < dimension_; ++d)
      if (p[d] < lo_[d] - tol || p[d] > hi_[d] + tol) return false;
    return true;
  }
  Bounds bounds() const override { return {lo_, hi_}; }

 private:
  Vec3 lo_, hi_;
  int dimension_;
};

class Sphere : public Shape {  // a disc (circle) in 2D
 public:
  Sphere(Vec3 centre, double radius) : centre_(centre), radius_(radius) {}
  bool contains(const Vec3& p) const override {
    return (p - centre_).norm() <= radius_ * (1 + kSurfaceTolerance);
  }
  Bounds bounds() const override {
    return {centre_ - Vec3::Constant(radius_), centre_ + Vec3::Constant(radius_)};
  }

 private:
  Vec3 centre_;
  double radius_;
};

class Cylinder : public Shape {  // 3D: axis through `centre`, `height` long, centred on it
 public:
  Cylinder(Vec3 centre, Vec3 axis, double radius, double height)
      : centre_(centre), axis_(axis.normalized()), radius_(radius), height_(height) {}
  bool contains(const Vec3& p) const override {
    const Vec3 d = p - centre_;
    const double along = d.dot(axis_);
    const double tol = kSurfaceTolerance * std::max(radius_, height_);
    return std::abs(along) <= height_ / 2 + tol && (d - along * axis_).norm() <= radius_ + tol;
  }
  Bounds bounds() const override {
    Vec3 ext;
    for (int d = 0; d < 3; ++d) {
      const double a = axis_[d];
      ext[d] = std::abs(a) * height_ / 2 + radius_ * std::sqrt(std::max(0.0, 1 - a * a));
    }
    return {centre_ - ext, centre_ + ext};
  }

 private:
  Vec3 centre_, axis_;
  double radius_, height_;
};

class HalfSpace : public Shape {  // the points on the side the normal points to
 public:
  HalfSpace(Vec3 point, Vec3 normal) : point_(point), normal_(normal.normalized()) {}
  bool contains(const Vec3& p) const override { return (p - point_).dot(normal_) >= 0; }
  Bounds bounds() const override { return {Vec3::Constant(-kInf), Vec3::Constant(kInf)}; }

 private:
  Vec3 point_, normal_;
};

const bool box_registered = register_shape("box", [](const CaseNode& n, int dim) {
  const Vec3 lo = n.required("min").as_vector(dim), hi = n.required("max").as_vector(dim);
  for (int d = 0; d < dim; ++d)
    if (!(hi[d] > lo[d])) n.fail("a box with max > min in every component");
  return std::unique_ptr<Shape>(new Box(lo, hi, dim));
});

const bool sphere_registered = register_shape("sphere", [](const CaseNode& n, int dim) {
  const Vec3 c = n.required("center").as_vector(dim);
  return std::unique_ptr<Shape>(new Sphere(c, n.required("radius").as_positive()));
});

const bool cylinder_registered = register_shape("cylinder", [](const CaseNode& n, int dim) {
  if (dim != 3) n.fail("a 3D body for a cylinder (in 2D a disc is type: sphere)");
  const Vec3 c = n.required("center").as_vector(3);
  Vec3 axis(0, 0, 1);
  if (auto a = n.optional("axis")) {
    axis = a->as_vector(3);
    if (axis.norm() == 0) a->fail("a non-zero axis");
  }
  return std::unique_ptr<Shape>(new Cylinder(c, axis, n.required("radius").as_positive(),
                                             n.required("height").as_positive()));
});

const bool half_space_registered = register_shape("half_space", [](const CaseNode& n, int dim) {
  const Vec3 p = n.required("point").as_vector(dim);
  const CaseNode nn = n.required("normal");
  const Vec3 normal = nn.as_vector(dim);
  if (normal.norm() == 0) nn.fail("a non-zero normal");
  return std::unique_ptr<Shape>(new HalfSpace(p, normal));
});

}  // namespace

}  // namespace ckpd
