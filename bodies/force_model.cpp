#include "bodies/force_model.hpp"

#include "bodies/body.hpp"
#include "bodies/point_kernel.hpp"

namespace ckpd {

const ForceModelKernels& force_model(const Body& body) {
  return body.model != nullptr ? *body.model : ckpd_kernels();
}

PointResult evaluate_point(const Body& body, std::size_t i, FamilyScratch& scratch) {
  return force_model(body).point(body, i, scratch);
}

}  // namespace ckpd
