// The CKPD model's kernels, instantiated once (ckpd_model.hpp has the law).
#include "bodies/ckpd_model.hpp"

#include "bodies/force_model_kernels.hpp"

namespace ckpd {

const ForceModelKernels& ckpd_kernels() {
  return kernels_of<CkpdModel>();
}

const ForceModelKernels& ckpd_seth_hill_kernels() {
  return kernels_of<CkpdSethHillModel>();
}

const ForceModelKernels& ckpd_conservative_kernels() {
  return kernels_of<CkpdConservativeModel>();
}

const ForceModelKernels& ckpd_seth_hill_conservative_kernels() {
  return kernels_of<CkpdSethHillConservativeModel>();
}

}  // namespace ckpd
