#include "bodies/body.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "bodies/census.hpp"
#include "bodies/damage.hpp"
#include "bodies/family_scratch.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/symmetric_kernel.hpp"

namespace ckpd {

namespace {

using Mat3 = Eigen::Matrix3d;

void check_definition(const BodyDefinition& d) {
  std::ostringstream msg;
  const std::string who = "body '" + d.name + "': ";
  if (d.dimension != 2 && d.dimension != 3) {
    msg << who << "dimension must be 2 or 3, got " << d.dimension;
  } else if (d.reference_position.empty()) {
    msg << who << "has no points (is the geometry smaller than the lattice spacing?)";
  } else if (d.volume.size() != d.reference_position.size()) {
    msg << who << "needs one volume per point";
  } else if (!(d.density > 0) || !std::isfinite(d.density)) {
    msg << who << "density must be positive, got " << d.density;
  } else if (!(d.horizon > 0) || !std::isfinite(d.horizon)) {
    msg << who << "horizon must be positive, got " << d.horizon;
  } else if (!(d.full_family_volume > 0)) {
    msg << who << "full family volume must be positive";
  } else if (!d.no_failure.empty() && d.no_failure.size() != d.reference_position.size()) {
    msg << who << "needs one no-failure flag per point";
  } else if (!(d.degenerate_fraction > 0 && d.degenerate_fraction < 1)) {
    msg << who << "degenerate fraction must be in (0, 1), got " << d.degenerate_fraction;
  } else if (!(d.critical_stretch > 0)) {
    msg << who << "critical stretch must be positive, got " << d.critical_stretch;
  } else if (!(d.inversion_penalty >= 0) || !std::isfinite(d.inversion_penalty)) {
    msg << who << "inversion penalty must be a finite factor >= 0, got " << d.inversion_penalty;
  } else if (d.inversion_penalty > 0 && d.model != nullptr && d.model->prepare != nullptr) {
    msg << who << "an inversion penalty is a CKPD option; this body's force model is "
        << d.model->name << " (bonds only: a strain measure m <= 0 is its barrier)";
  } else if (d.inversion_penalty > 0 &&
             (d.dimension == 3 ? d.constants.c3 == 0 : d.constants.c2 == 0)) {
    msg << who << "an inversion penalty needs the " << (d.dimension == 3 ? "three" : "two")
        << "-neighbour interactions, which this material does not have (C"
        << (d.dimension == 3 ? "3" : "2") << " = 0 because lambda = mu)";
  } else if (!std::isfinite(d.strain_measure)) {
    msg << who << "strain measure m must be a finite number, got " << d.strain_measure;
  } else if (d.strain_measure != 0.5 && d.model != nullptr) {
    msg << who << "a strain measure (m = " << d.strain_measure
        << ") is a CKPD option; this body's force model is " << d.model->name;
  } else if (d.force_form != ForceForm::own_family && d.model != nullptr) {
    msg << who << "force_form " << to_string(d.force_form)
        << " is a CKPD option; this body's force model is " << d.model->name;
  } else if (d.dimension == 2 && d.constants.c3 != 0) {
    msg << who << "a 2D body has no three-neighbour interactions (C3 must be 0)";
  } else {
    for (std::size_t i = 0; i < d.volume.size(); ++i) {
      if (!(d.volume[i] > 0)) {
        msg << who << "point " << i << " has non-positive volume " << d.volume[i];
        break;
      }
      if (d.dimension == 2 && d.reference_position[i].z() != 0) {
        msg << who << "2D point " << i << " is not in the z = 0 plane";
        break;
      }
    }
    if (msg.str().empty()) return;
  }
  throw std::invalid_argument(msg.str());
}

// A point's family as the sorted list of its reference offsets in units of horizon * 2^-30.
// Points with equal lists (the interior of a lattice: almost every point) have the same
// interaction census, so it is computed once per distinct list. Offsets that differ by less
// than a billionth of the horizon are the same lattice offset up to round-off.
using QuantizedFamily = std::vector<std::array<std::int64_t, 3>>;

QuantizedFamily quantized_family(const Body& body, std::size_t i) {
  const double quantum = body.horizon * std::ldexp(1.0, -30);
  QuantizedFamily f;
  f.reserve(body.family.family_size(i));
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
    const Vec3 d = body.reference_position[body.family.neighbour[k]] - body.reference_position[i];
    f.push_back({std::llround(d.x() / quantum), std::llround(d.y() / quantum),
                 std::llround(d.z() / quantum)});
  }
  std::sort(f.begin(), f.end());
  return f;
}

std::uint64_t hash_family(const QuantizedFamily& f) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the integers
  for (const auto& o : f)
    for (std::int64_t v : o) {
      h ^= static_cast<std::uint64_t>(v);
      h *= 1099511628211ull;
    }
  return h;
}

}  // namespace

std::array<double, 3> conservative_bound_scale(const Body& body, std::size_t i) {
  const std::vector<double>* dv[3] = {&body.dv1, &body.dv2, &body.dv3};
  std::array<double, 3> r{1, 1, 1};
  for (int f = 0; f < 3; ++f) {
    const double own = body.volume[i] * (*dv[f])[i];
    if (!(own > 0)) continue;
    double most = own;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::uint32_t j = body.family.neighbour[k];
      most = std::max(most, body.volume[j] * (*dv[f])[j]);
    }
    r[static_cast<std::size_t>(f)] = most / own;
  }
  return r;
}

std::uint64_t Body::total_two_neighbour() const {
  std::uint64_t t = 0;
  for (auto n : n2) t += n;
  return t;
}

std::uint64_t Body::total_three_neighbour() const {
  std::uint64_t t = 0;
  for (auto n : n3) t += n;
  return t;
}

double Body::mass() const {
  double m = 0;
  for (double v : volume) m += density * v;
  return m;
}

DamageRule damage_rule_from_string(const std::string& name) {
  if (name == "centre_bonds") return DamageRule::centre_bonds;
  if (name == "all_edges") return DamageRule::all_edges;
  throw std::invalid_argument("damage rule must be 'centre_bonds' or 'all_edges', got '" + name +
                              "'");
}

std::string to_string(DamageRule rule) {
  return rule == DamageRule::all_edges ? "all_edges" : "centre_bonds";
}

ForceForm force_form_from_string(const std::string& name) {
  if (name == "own_family") return ForceForm::own_family;
  if (name == "energy_consistent") return ForceForm::energy_consistent;
  throw std::invalid_argument("force form must be 'own_family' or 'energy_consistent', got '" +
                              name + "'");
}

std::string to_string(ForceForm form) {
  return form == ForceForm::energy_consistent ? "energy_consistent" : "own_family";
}

Body make_body(BodyDefinition def) {
  check_definition(def);
  Body body;
  body.name = def.name;
  body.dimension = def.dimension;
  body.density = def.density;
  body.horizon = def.horizon;
  body.constants = def.constants;
  body.critical_stretch = def.critical_stretch;
  body.damage_enabled = std::isfinite(def.critical_stretch);
  body.degenerate_fraction = def.degenerate_fraction;
  body.inversion_penalty = def.inversion_penalty;
  body.damage_rule = def.damage_rule;
  body.model = def.model;
  body.strain_measure = def.strain_measure;
  body.state_based = def.state_based;
  body.force_form = def.force_form;
  if (def.model == nullptr && def.force_form == ForceForm::energy_consistent) {
    body.model = def.strain_measure != 0.5 ? &ckpd_seth_hill_conservative_kernels()
                                           : &ckpd_conservative_kernels();
  } else if (def.model == nullptr && def.strain_measure != 0.5) {
    body.model = &ckpd_seth_hill_kernels();
  }
  body.reference_position = std::move(def.reference_position);
  body.volume = std::move(def.volume);
  body.no_failure = std::move(def.no_failure);
  const std::size_t n = body.size();

  body.family = build_bond_family(body.reference_position, body.horizon);
  for (std::size_t i = 0; i < n; ++i) {
    if (body.family.family_size(i) == 0) {
      const Vec3& p = body.reference_position[i];
      std::ostringstream msg;
      msg << "body '" << body.name << "': point " << i << " at (" << p.x() << ", " << p.y() << ", "
          << p.z() << ") has no neighbour within the horizon " << body.horizon
          << " m (a body needs more than one point, and every point needs a bond)";
      throw std::invalid_argument(msg.str());
    }
  }
  body.bond_intact.assign(body.family.bond_entries(), 1);

  body.beta.resize(n);
  body.dv1.resize(n);
  body.dv2.assign(n, 0);
  body.dv3.assign(n, 0);
  body.n2.assign(n, 0);
  body.n3.assign(n, 0);
  body.stiffness_bound.resize(n);

  const double ball = body.dimension == 3 ? 4.0 / 3.0 * std::numbers::pi * std::pow(body.horizon, 3)
                                          : std::numbers::pi * body.horizon * body.horizon;
  const bool pairs = body.has_pairs(), triples = body.has_triples();
  // Group points by family shape, then take one census per group.
  std::vector<std::uint64_t> family_hash(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) family_hash[i] = hash_family(quantized_family(body, i));
  std::vector<std::size_t> group(n);
  std::vector<std::size_t> representative;
  {
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> groups_by_hash;
    for (std::size_t i = 0; i < n; ++i) {
      auto& candidates = groups_by_hash[family_hash[i]];
      std::size_t found = representative.size();
      if (!candidates.empty()) {
        const QuantizedFamily mine = quantized_family(body, i);
        for (std::size_t g : candidates)
          if (quantized_family(body, representative[g]) == mine) {
            found = g;
            break;
          }
      }
      if (found == representative.size()) {
        representative.push_back(i);
        candidates.push_back(found);
      }
      group[i] = found;
    }
  }
  std::vector<PointCensus> census(representative.size());
#pragma omp parallel
  {
    FamilyScratch scratch;
#pragma omp for schedule(dynamic, 1)
    for (std::size_t g = 0; g < representative.size(); ++g) {
      scratch.load(body, representative[g], false, pairs || triples);
      census[g] = force_model(body).census(body, scratch);
    }
  }

  std::string error;
  constexpr double kBetaTolerance = 1e-9;
  double beta_max_raw = 0;
  std::size_t beta_capped = 0;
#pragma omp parallel for schedule(static) reduction(max : beta_max_raw) reduction(+ : beta_capped)
  for (std::size_t i = 0; i < n; ++i) {
    double family_volume = 0;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      family_volume += body.volume[body.family.neighbour[k]];
    const double raw_beta = family_volume / def.full_family_volume;
    beta_max_raw = std::max(beta_max_raw, raw_beta);
    const bool over = raw_beta > 1 + kBetaTolerance;
    if (over && def.cap_beta) ++beta_capped;
    const double beta = over && def.cap_beta ? 1.0 : raw_beta;
    body.beta[i] = beta;
    const PointCensus& c = census[group[i]];
    const double vh = beta * ball;
    const std::size_t n1 = body.family.family_size(i);
    body.n2[i] = c.n2;
    body.n3[i] = c.n3;
    body.dv1[i] = n1 ? vh / static_cast<double>(n1) : 0;
    body.dv2[i] = c.n2 ? vh * vh / c.n2 : 0;
    body.dv3[i] = c.n3 ? vh * vh * vh / c.n3 : 0;
    const Mat3 q = std::abs(body.constants.c1) * body.dv1[i] * c.q1 +
                   std::abs(body.constants.c2) * body.dv2[i] * c.q2 +
                   std::abs(body.constants.c3) * body.dv3[i] * c.q3;
    body.stiffness_bound[i] =
        Eigen::SelfAdjointEigenSolver<Mat3>(q, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    if (over && !def.cap_beta) {
#pragma omp critical
      if (error.empty()) {
        std::ostringstream msg;
        msg << "body '" << body.name << "': point " << i << " has a family volume " << raw_beta
            << " times the full family volume; the point volumes or the full family volume "
               "are inconsistent (irregular point clouds: see `beta: capped`)";
        error = msg.str();
      }
    }
  }
  if (!error.empty()) throw std::invalid_argument(error);
  if (body.force_form == ForceForm::energy_consistent) {
    // A set's weight at point i is the mean of V^c dVn^c over its vertices, over V^i: at most
    // the largest V^c dVn^c of i's closed family over V^i dVn^i times i's own-family weight, so
    // the own-family bound scaled by that ratio bounds it (THEORY.md section 2b).
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const PointCensus& c = census[group[i]];
      const std::array<double, 3> r = conservative_bound_scale(body, i);
      const Mat3 q = std::abs(body.constants.c1) * body.dv1[i] * r[0] * c.q1 +
                     std::abs(body.constants.c2) * body.dv2[i] * r[1] * c.q2 +
                     std::abs(body.constants.c3) * body.dv3[i] * r[2] * c.q3;
      body.stiffness_bound[i] =
          Eigen::SelfAdjointEigenSolver<Mat3>(q, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    }
  }
  body.beta_cap = def.cap_beta;
  body.beta_capped_points = beta_capped;
  body.beta_max_raw = beta_max_raw;

  body.displacement.assign(n, Vec3::Zero());
  body.velocity.assign(n, Vec3::Zero());
  body.acceleration.assign(n, Vec3::Zero());
  body.external_force_density.assign(n, Vec3::Zero());
  body.force_density.assign(n, Vec3::Zero());
  body.strain_energy_density.assign(n, 0.0);

  body.screens = set_screens(body);
  for (const Precrack& crack : def.precracks) apply_precrack(body, crack);
  if (def.lattice_stencil) {
    StencilBuild stencil = build_lattice_stencil(body);
    body.stencil = std::move(stencil.stencil);
    body.stencil_note = std::move(stencil.reason);
  } else {
    body.stencil_note = "turned off (lattice_stencil: false)";
  }
  if (!body.has_pairs() && !body.has_triples())
    body.upper_bonds = build_upper_bonds(body.reference_position, body.family);
  else if (!body.stencil)
    body.upper_rows = build_upper_rows(body);
  if (force_model(body).prepare != nullptr) force_model(body).prepare(body);
  return body;
}

StiffnessTerms stiffness_terms(const Body& body, std::size_t i) {
  // A model that sets its own bound (ForceModelKernels::prepare) has bonds only.
  if (force_model(body).prepare != nullptr) return {body.stiffness_bound[i], 0, 0};
  FamilyScratch scratch;
  scratch.load(body, i, false, body.has_pairs() || body.has_triples());
  const PointCensus c = force_model(body).census(body, scratch);
  auto largest = [](const Mat3& m) {
    return Eigen::SelfAdjointEigenSolver<Mat3>(m, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  };
  const std::array<double, 3> r = body.force_form == ForceForm::energy_consistent
                                      ? conservative_bound_scale(body, i)
                                      : std::array<double, 3>{1, 1, 1};
  return {largest(std::abs(body.constants.c1) * body.dv1[i] * r[0] * c.q1),
          largest(std::abs(body.constants.c2) * body.dv2[i] * r[1] * c.q2),
          largest(std::abs(body.constants.c3) * body.dv3[i] * r[2] * c.q3)};
}

double strain_energy(const Body& body) {
  double e = 0;
  for (std::size_t i = 0; i < body.size(); ++i)
    if (body.books(i)) e += body.strain_energy_density[i] * body.volume[i];
  return e;
}

StableStep stable_step(const Body& body) {
  // Central differences are stable for dt <= 2 / omega_max. For the linearised system
  // rho u'' = -K u, omega_max^2 = lambda_max(K) / rho, and lambda_max(K) <= max_i k_i where
  // k_i is the largest eigenvalue of the directional row-sum matrix built in census_point:
  // by Cauchy-Schwarz (sum_c g_c.u_c)^2 <= (sum_c |g_c|) sum_c (g_c.u_c)^2 / |g_c| for every
  // interaction, and each interaction's gradient at a point does not depend on whose family it
  // is counted in.
  StableStep s;
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (body.stiffness_bound[i] <= 0) continue;
    const double dt = 2.0 * std::sqrt(body.density / body.stiffness_bound[i]);
    if (dt < s.dt) s = {dt, i};
  }
  return s;
}

}  // namespace ckpd
