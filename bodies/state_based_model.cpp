// The nonlinear ordinary state-based solid (state_based_model.hpp): its kernels and table.
#include "bodies/state_based_model.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>

#include "bodies/census.hpp"
#include "bodies/damage.hpp"
#include "bodies/point_kernel.hpp"
#include "bodies/symmetric_kernel.hpp"

namespace ckpd {

namespace {

// eps(c) and d eps / dc * 2 = c^(m-1) of the Seth-Hill bond strain.
struct Strain {
  double eps, g;
};

inline Strain seth_hill(double m, double c) {
  if (m == 0.5) {
    const double s = std::sqrt(c);
    return {s - 1, 1 / s};
  }
  if (m == 0) return {0.5 * std::log(c), 1 / c};
  const double cm = std::pow(c, m);
  return {(cm - 1) / (2 * m), cm / c};
}

// The weight's shape (3r + delta)(delta - r)^3, without its constant.
inline double shape(double r, double delta) {
  if (!(r < delta)) return 0;
  const double s = delta - r;
  return (3 * r + delta) * s * s * s;
}

double weight_constant(int dimension, double delta) {
  return dimension == 2 ? 10 / (std::numbers::pi * std::pow(delta, 6))
                        : 315 / (16 * std::numbers::pi * std::pow(delta, 7));
}

// What every loop needs of the body's constants.
struct Law {
  double lambda_bar, mu_bar, m, wk, delta;
  explicit Law(const Body& b)
      : lambda_bar(b.state_based.lambda_bar),
        mu_bar(b.state_based.mu_bar),
        m(b.state_based.m),
        wk(b.state_based.weight_scale * weight_constant(b.dimension, b.horizon)),
        delta(b.horizon) {}
  double weight(double L) const { return wk * shape(L, delta); }
};

// One stored bond of point i's row at the current displacement.
struct BondState {
  std::uint32_t j;
  Vec3 Y;
  double L2, L, w, eps, g;
};

inline BondState bond_state(const Body& b, const Law& law, std::size_t i, std::size_t k) {
  BondState s;
  s.j = b.family.neighbour[k];
  const Vec3 xi = b.reference_position[s.j] - b.reference_position[i];
  s.Y = xi + (b.displacement[s.j] - b.displacement[i]);
  s.L2 = xi.squaredNorm();
  s.L = std::sqrt(s.L2);
  s.w = law.weight(s.L);
  const Strain e = seth_hill(law.m, s.Y.squaredNorm() / s.L2);
  s.eps = e.eps;
  s.g = e.g;
  return s;
}

double theta_of(const Body& b, const Law& law, std::size_t i) {
  double t = 0;
  for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
    if (!b.bond_intact[k]) continue;
    const BondState s = bond_state(b, law, i, k);
    t += s.w * s.eps * b.volume[s.j];
  }
  return t;
}

double psi_of(const Body& b, const Law& law, std::size_t i) {
  double t = 0, q = 0;
  for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
    if (!b.bond_intact[k]) continue;
    const BondState s = bond_state(b, law, i, k);
    t += s.w * s.eps * b.volume[s.j];
    q += s.w * s.eps * s.eps * b.volume[s.j];
  }
  return 0.5 * law.lambda_bar * t * t + law.mu_bar * q;
}

// The force density on i given every point's theta (theta_at(j)), and psi_i.
template <class Theta>
std::pair<Vec3, double> force_of(const Body& b, const Law& law, std::size_t i, double theta_i,
                                 Theta theta_at) {
  Vec3 f = Vec3::Zero();
  double q = 0;
  for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
    if (!b.bond_intact[k]) continue;
    const BondState s = bond_state(b, law, i, k);
    const double vw = b.volume[s.j] * s.w;
    const double t =
        vw * s.g / s.L2 * (law.lambda_bar * (theta_i + theta_at(s.j)) + 4 * law.mu_bar * s.eps);
    f += t * s.Y;
    q += vw * s.eps * s.eps;
  }
  return {f, 0.5 * law.lambda_bar * theta_i * theta_i + law.mu_bar * q};
}

// Per-thread scratch of the whole-body passes (kept by the calling thread between calls; the
// workers write through references to it).
std::vector<double>& theta_scratch() {
  thread_local std::vector<double> theta;
  return theta;
}

void compute_theta(const Body& b, const Law& law, std::vector<double>& theta) {
  const std::size_t n = b.size();
  theta.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) theta[i] = theta_of(b, law, i);
}

SymmetricKernelStats compute(Body& b, bool with_energy, SymmetricKernelWorkspace&) {
  const Law law(b);
  std::vector<double>& theta = theta_scratch();
  compute_theta(b, law, theta);
  const std::size_t n = b.size();
  std::uint64_t intact = 0;
#pragma omp parallel for schedule(static) reduction(+ : intact)
  for (std::size_t i = 0; i < n; ++i) {
    const auto [f, psi] = force_of(b, law, i, theta[i], [&](std::size_t j) { return theta[j]; });
    b.force_density[i] = f;
    if (with_energy) b.strain_energy_density[i] = psi;
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k)
      if (b.bond_intact[k] && i < b.family.neighbour[k]) ++intact;
  }
  SymmetricKernelStats stats;
  stats.bonds = intact;
  return stats;
}

PointResult point(const Body& b, std::size_t i, FamilyScratch&) {
  const Law law(b);
  const auto [f, psi] =
      force_of(b, law, i, theta_of(b, law, i), [&](std::size_t j) { return theta_of(b, law, j); });
  PointResult r;
  r.force_density = f;
  r.w1 = 2 * psi;  // strain_energy_density() = w1 / 2
  return r;
}

// Marks in `fails` (one flag per stored bond) every intact bond that fails now, with theta the
// current dilatation. Both stored directions get the same decision (the test is symmetric).
std::size_t mark_failures(const Body& b, const Law& law, const std::vector<double>& theta,
                          std::vector<std::uint8_t>& fails) {
  const std::size_t n = b.size();
  const bool protect = !b.no_failure.empty();
  const double beta = b.state_based.failure_beta;
  fails.assign(b.family.bond_entries(), 0);
  std::size_t failed = 0;
#pragma omp parallel for schedule(static) reduction(+ : failed)
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
      if (!b.bond_intact[k]) continue;
      const std::uint32_t j = b.family.neighbour[k];
      if (protect && (b.no_failure[i] || b.no_failure[j])) continue;
      const BondState s = bond_state(b, law, i, k);
      if (!(s.eps >= 0)) continue;
      const double energy =
          0.5 * law.lambda_bar * s.eps * (theta[i] + theta[j]) + law.mu_bar * s.eps * s.eps;
      if (energy * s.L2 >= beta) {
        fails[k] = 1;
        if (i < j) ++failed;
      }
    }
  }
  return failed;
}

std::size_t update_failure(Body& b) {
  if (!b.damage_enabled || !std::isfinite(b.state_based.failure_beta)) return 0;
  const Law law(b);
  std::vector<double>& theta = theta_scratch();
  compute_theta(b, law, theta);
  thread_local std::vector<std::uint8_t> kept;
  std::vector<std::uint8_t>& fails = kept;
  const std::size_t failed = mark_failures(b, law, theta, fails);
  if (failed == 0) return 0;
  for (std::size_t k = 0; k < fails.size(); ++k)
    if (fails[k]) b.bond_intact[k] = 0;
  return failed;
}

FailureUpdate fail_and_book(Body& b, double half_drift) {
  FailureUpdate result;
  if (!b.damage_enabled || !std::isfinite(b.state_based.failure_beta)) return result;
  const Law law(b);
  std::vector<double>& theta = theta_scratch();
  compute_theta(b, law, theta);
  thread_local std::vector<std::uint8_t> kept;
  std::vector<std::uint8_t>& fails = kept;
  result.failed = mark_failures(b, law, theta, fails);
  if (result.failed == 0) return result;
  // Only the ends of a failing bond see psi change (psi_p depends on p's own bonds alone).
  const std::size_t n = b.size();
  std::vector<std::uint32_t> points;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k)
      if (fails[k]) {
        points.push_back(static_cast<std::uint32_t>(i));
        break;
      }
  // Booked at the step's midpoint u - half_drift v (damage.hpp), decided at u (above).
  std::vector<Vec3> end_of_step;
  if (half_drift != 0) {
    end_of_step = b.displacement;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) b.displacement[i] -= half_drift * b.velocity[i];
  }
  std::vector<double> before(points.size()), after(points.size());
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < points.size(); ++p) before[p] = psi_of(b, law, points[p]);
  for (std::size_t k = 0; k < fails.size(); ++k)
    if (fails[k]) b.bond_intact[k] = 0;
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < points.size(); ++p) after[p] = psi_of(b, law, points[p]);
  // Copied back, not moved: the displacement keeps its buffer (numpy views of it).
  if (half_drift != 0) std::copy(end_of_step.begin(), end_of_step.end(), b.displacement.begin());
  double dissipated = 0;
  for (std::size_t p = 0; p < points.size(); ++p)
    dissipated += b.volume[points[p]] * (before[p] - after[p]);
  result.dissipated = dissipated;
  return result;
}

// The model keeps no per-set census: its stiffness bound is set by prepare().
PointCensus census(const Body&, const FamilyScratch&) {
  return {};
}

// The largest sum of w V over a family (all bonds, before cuts), continuum-normalised weight.
double fullest_family(const Body& b) {
  const double c = weight_constant(b.dimension, b.horizon);
  double fullest = 0;
  const std::size_t n = b.size();
#pragma omp parallel for schedule(static) reduction(max : fullest)
  for (std::size_t i = 0; i < n; ++i) {
    double s = 0;
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
      const std::uint32_t j = b.family.neighbour[k];
      s += c * shape((b.reference_position[j] - b.reference_position[i]).norm(), b.horizon) *
           b.volume[j];
    }
    fullest = std::max(fullest, s);
  }
  return fullest;
}

void prepare(Body& b) {
  // The body-wide weight factor: tr_w(1) = d for the fullest family.
  const double fullest = fullest_family(b);
  if (!(fullest > 0))
    throw std::invalid_argument("body '" + b.name +
                                "': the state-based weight vanishes on every family (no bond "
                                "shorter than the horizon)");
  b.state_based.weight_scale = b.dimension / fullest;
  if (std::isfinite(b.state_based.failure_beta)) b.damage_enabled = true;
  state_based_stiffness_bound(b, b.stiffness_bound);
}

}  // namespace

const ForceModelKernels& state_based_kernels() {
  // No linearisation: the far field needs a model with per-set linearisations.
  static const ForceModelKernels table{"state_based", compute, point,   census, update_failure,
                                       fail_and_book, prepare, nullptr, nullptr};
  return table;
}

double state_based_weight(int dimension, double r, double horizon) {
  return weight_constant(dimension, horizon) * shape(r, horizon);
}

double state_based_failure_beta(int dimension, double horizon, double fracture_energy) {
  // THEORY.md: Gc = 4 beta int_0^delta w dr (2D), 2 pi beta int_0^delta w r dr (3D).
  return dimension == 2 ? std::numbers::pi * horizon * fracture_energy / 16
                        : 16 * horizon * fracture_energy / 63;
}

StateBasedConstants state_based_constants(int dimension, double lambda, double mu) {
  StateBasedConstants k;
  k.lambda_bar = lambda - mu;
  k.mu_bar = dimension == 2 ? 2 * mu : 2.5 * mu;
  return k;
}

void state_based_dilatation(const Body& body, std::vector<double>& theta) {
  compute_theta(body, Law(body), theta);
}

void state_based_energy_density(const Body& body, std::vector<double>& psi) {
  const Law law(body);
  psi.resize(body.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < body.size(); ++i) psi[i] = psi_of(body, law, i);
}

Eigen::Matrix3d state_based_point_kirchhoff_stress(const Body& body, std::size_t i) {
  const Law law(body);
  const double theta_i = theta_of(body, law, i);
  Eigen::Matrix3d tau = Eigen::Matrix3d::Zero();
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
    if (!body.bond_intact[k]) continue;
    const BondState s = bond_state(body, law, i, k);
    const double t =
        (law.lambda_bar * theta_i + 2 * law.mu_bar * s.eps) * s.w * body.volume[s.j] * s.g / s.L2;
    tau.noalias() += t * s.Y * s.Y.transpose();
  }
  return tau;
}

void state_based_free_surface(const Body& body, std::vector<double>& D, const Body* whole) {
  Law law(body);
  // Bodies of other models: the same weight, normalised the same way.
  if (body.state_based.weight_scale == 0) {
    const double fullest = fullest_family(whole ? *whole : body);
    law.wk =
        fullest > 0 ? body.dimension / fullest * weight_constant(body.dimension, body.horizon) : 0;
  }
  D.resize(body.size());
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < body.size(); ++i) {
    double t = 0;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      if (!body.bond_intact[k]) continue;
      const std::uint32_t j = body.family.neighbour[k];
      t += law.weight((body.reference_position[j] - body.reference_position[i]).norm()) *
           body.volume[j];
    }
    D[i] = 1 - t / body.dimension;
  }
}

void state_based_stiffness_bound(const Body& b, std::vector<double>& bound) {
  // THEORY.md: E = sum_i V_i psi_i. Each term's Hessian is bounded by a block-diagonal matrix
  // (Cauchy-Schwarz for the squared terms, |x_p - x_j|^2 <= 2 |x_p|^2 + 2 |x_j|^2 for the
  // curvature of eps); lambda_max(M^-1 K) <= max_p lambda_max(Q_p) / rho.
  const Law law(b);
  const std::size_t n = b.size();
  std::vector<double> theta, A(n);
  compute_theta(b, law, theta);
  const double curvature = std::max(1.0, std::abs(2 * law.m - 1));
  // A_i = sum_c |d theta_i / d y_c|.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    double s = 0;
    Vec3 own = Vec3::Zero();
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
      if (!b.bond_intact[k]) continue;
      const BondState st = bond_state(b, law, i, k);
      const Vec3 g = (st.w * b.volume[st.j] * st.g / st.L2) * st.Y;
      s += g.norm();
      own += g;
    }
    A[i] = s + own.norm();
  }
  bound.resize(n);
  const double lb = std::abs(law.lambda_bar);
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < n; ++p) {
    Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();
    Vec3 own = Vec3::Zero();
    double iso = 0;
    for (std::size_t k = b.family.offset[p]; k < b.family.offset[p + 1]; ++k) {
      if (!b.bond_intact[k]) continue;
      const BondState st = bond_state(b, law, p, k);
      const double gn = st.g * std::sqrt(st.Y.squaredNorm()) / st.L2;  // |d eps / d Y|
      if (!(gn > 0)) continue;
      const Vec3 e = st.Y.normalized();
      const double wv = st.w * b.volume[st.j];
      // mu_bar: 2 mu_bar V_p V_j w eps^2 per bond; lambda_bar: p as a neighbour of j.
      Q += (8 * law.mu_bar * wv * gn * gn + lb * b.volume[st.j] * A[st.j] * st.w * gn) *
           (e * e.transpose());
      own += (wv * st.g / st.L2) * st.Y;
      // Curvature of eps, |d2 eps / dY2| <= c^(m-1) / L^2 max(1, |2m - 1|), both orders.
      const double sp = law.lambda_bar * theta[p] + 2 * law.mu_bar * st.eps;
      const double sj = law.lambda_bar * theta[st.j] + 2 * law.mu_bar * st.eps;
      iso += 2 * wv * curvature * st.g / st.L2 * (std::abs(sp) + std::abs(sj));
    }
    const double on = own.norm();
    if (on > 0) Q += lb * A[p] / on * (own * own.transpose());
    Q += iso * Eigen::Matrix3d::Identity();
    if (b.dimension == 2) Q(2, 2) = 0;
    bound[p] =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Q, Eigen::EigenvaluesOnly).eigenvalues()(2);
  }
}

}  // namespace ckpd
