#pragma once
// The plain path of the CKPD stiffness bound at the current displacement
// (bodies/current_stiffness.hpp): the same bound, evaluated set by set from each point with no
// shared geometry. Linked by the tests only: the engine calls the optimised bound.
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

void reference_ckpd_current_stiffness_bound(const Body& body, std::vector<double>& bound,
                                            std::vector<double>* shrink_time = nullptr);

}  // namespace ckpd
