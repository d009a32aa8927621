#pragma once
// The pieces of the current-state stiffness bound shared by its two evaluations
// (bodies/current_stiffness.cpp, once per set; reference/current_stiffness.cpp, from every
// vertex): the measure's tangent at a ratio, the shrink time of a measure, relative velocities.
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/ckpd_model.hpp"
#include "bodies/family_scratch.hpp"

namespace ckpd::current_stiffness_detail {

// The closed forms take the ratio r itself: the general tangent_at works from r - 1, which
// loses r's relative precision as r -> 0 (a set squeezed to 1e-8 of its volume), where the
// bound matters most.
// model.tangent_at with closed forms for the measures in use with m <= 0 (m = 0: one log;
// m = -1/2: rational), the same values to rounding: the transcendental functions of the
// general form (log1p, expm1, exp per set) were a fifth of the bound's time.
template <class Model>
inline void tangent(const Model& model, double r, double penalty, double& slope,
                    double& curvature) {
  if constexpr (std::is_same_v<Model, CkpdSethHillModel>) {
    const double m = model.strain.m;
    if (m == 0) {
      const double e = std::log(r), ir = 1 / r;  // e_0 = log r, r^(2m - 1) = 1 / r
      slope = e * ir + penalty;
      curvature = (1 - e) * ir * ir;
      return;
    }
    if (m == -0.5) {
      const double ir = 1 / r, e = 1 - ir, g = ir * ir;  // e = 1 - 1/r, r^(2m - 1) = r^-2
      slope = e * g + penalty;
      curvature = g * g - 2 * e * g * ir;
      return;
    }
  }
  model.tangent_at(r, penalty, slope, curvature);
}

// The time a measure m of a set (or bond) takes to reach zero at its rate dm/dt when shrinking.
inline void shrink(double measure, double rate, double& time) {
  if (rate < 0) time = std::min(time, measure / -rate);
}

// w[a]: the velocity of slot a's point relative to point i's.
inline void relative_velocities(const Body& body, std::size_t i, const FamilyScratch& s,
                                std::vector<Vec3>& w) {
  w.resize(s.size());
  for (std::size_t a = 0; a < s.size(); ++a) w[a] = body.velocity[s.index[a]] - body.velocity[i];
}

}  // namespace ckpd::current_stiffness_detail
