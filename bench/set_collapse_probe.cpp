// A probe of a CKPD body's sets during a run (docs/STABILITY.md, "50 % compression with the
// Seth-Hill strain measures"): after every EVERY-th step, the smallest bond ratio l/L, the
// smallest tetrahedron volume ratio |v|/|V| (with that set's shape |V| / (L L L)), the counts of
// inverted sets and of sets below 10 % and 1 % of their volume (each counted once per vertex
// that holds it), the sets' and bonds' energies, the largest bonds-only stiffening factor (the
// guard's first estimate), the stable step 2 sqrt(rho / k) with the current-state bound of
// bodies/current_stiffness.hpp (no safety factor, no contact stiffness) and with the bonds-only
// estimate. Usage: set_collapse_probe CASE EVERY [--set key=value ...]; add
// --set time.allow_unstable_dt=true to look past the point where the guard stops the run.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bodies/current_stiffness.hpp"
#include "bodies/family_scratch.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

using namespace ckpd;

namespace {

double em(double m, double r) {
  return m == 0 ? std::log(r) : (std::pow(r, 2 * m) - 1) / (2 * m);
}
// d/dr [e_m r^(2m-1)]
double hcurv(double m, double r) {
  return std::pow(r, 4 * m - 2) + (2 * m - 1) * em(m, r) * std::pow(r, 2 * m - 2);
}

struct Stats {
  double min_tet_r = 1e300, min_bond_r = 1e300;
  std::size_t tets = 0, inverted = 0, r01 = 0, r001 = 0;
  double tet_energy = 0, bond_energy = 0;
  double max_tet_factor = 0;  // max over points of the current bound over the reference one
  std::size_t max_tet_point = 0;
  double max_bond_factor = 0;               // the guard's factor
  double max_total_cur = 0, max_guard = 0;  // largest current bound, bonds-only estimate
  double min_ref_V_rel_at_min = 0;
};

Stats measure(const Body& b, bool all_points) {
  Stats s;
  const double m = b.strain_measure;
  FamilyScratch sc;
  for (std::size_t i = 0; i < b.size(); ++i) {
    sc.load(b, i, true, true);
    double bond_factor = 1;
    for (std::size_t a = 0; a < sc.size(); ++a) {
      const double L = sc.length[a], l = sc.cur[a].norm(), r = l / L;
      s.min_bond_r = std::min(s.min_bond_r, r);
      const double e = em(m, r);
      s.bond_energy += 0.5 * b.constants.c1 * L * e * e * b.dv1[i] * b.volume[i] / 2;
      const double along = hcurv(m, r), across = std::abs(e) * std::pow(r, 2 * m - 2);
      bond_factor = std::max(bond_factor, std::abs(along) + across);
    }
    if (b.constants.c3 != 0) {
      sc.for_each_triple([&](std::size_t a, std::size_t bb, std::size_t c) {
        const Vec3 P = sc.ref[a], Q = sc.ref[bb], R = sc.ref[c];
        const double sV = P.dot(Q.cross(R)), V = std::abs(sV);
        if (V <= b.degenerate_fraction * sc.length[a] * sc.length[bb] * sc.length[c]) return;
        const Vec3 p = sc.cur[a], q = sc.cur[bb], r = sc.cur[c];
        const double v = p.dot(q.cross(r));
        const double rr = std::abs(v) / V;
        ++s.tets;
        if (v * sV < 0) ++s.inverted;
        if (rr < 0.1) ++s.r01;
        if (rr < 0.01) ++s.r001;
        if (rr < s.min_tet_r) {
          s.min_tet_r = rr;
          s.min_ref_V_rel_at_min = V / (sc.length[a] * sc.length[bb] * sc.length[c]);
        }
        const double e = em(m, rr);
        s.tet_energy += 0.75 * b.constants.c3 * b.dv3[i] * V * e * e * b.volume[i];
      });
    }
    s.max_bond_factor = std::max(s.max_bond_factor, bond_factor);
    s.max_guard = std::max(s.max_guard, bond_factor * b.stiffness_bound[i]);
    if (!all_points) break;
  }
  std::vector<double> k;
  ckpd_current_stiffness_bound(b, k);
  for (std::size_t i = 0; i < b.size(); ++i) {
    s.max_total_cur = std::max(s.max_total_cur, k[i]);
    if (k[i] / b.stiffness_bound[i] > s.max_tet_factor) {
      s.max_tet_factor = k[i] / b.stiffness_bound[i];
      s.max_tet_point = i;
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "set_collapse_probe CASE EVERY [--set key=value ...]\n");
    return 2;
  }
  std::vector<std::string> overrides;
  for (int a = 3; a + 1 < argc; a += 2) overrides.push_back(argv[a + 1]);
  Scene scene = load_scene(argv[1], overrides);
  const long every = std::stol(argv[2]);
  Simulation sim(scene);
  std::size_t bi = 0;
  for (std::size_t k = 0; k < scene.bodies.size(); ++k)
    if (!scene.bodies[k].rigid) bi = k;
  const Body& b = scene.bodies[bi].body;
  std::printf("# dt %.4g estimate %.4g m %g c1 %.4g c2 %.4g c3 %.4g\n", sim.step_choice().dt,
              sim.step_choice().estimate, b.strain_measure, b.constants.c1, b.constants.c2,
              b.constants.c3);
  std::printf(
      "step t min_bond_r min_tet_r Vrel_at_min tets inverted r<0.1 r<0.01 tetE bondE "
      "bond_factor cur_factor dt_cur dt_guard Ek Es\n");
  const double dt = sim.step_choice().dt;
  std::vector<std::string> lastlines;
  while (true) {
    try {
      sim.advance(true);
    } catch (const std::exception& e) {
      std::printf("# stopped: %s\n", e.what());
      Stats s = measure(b, true);
      std::printf("%lld %.4g %.4f %.3g %.3g %zu %zu %zu %zu %.4g %.4g %.3g %.3g %.3g %.3g\n",
                  sim.step(), sim.time(), s.min_bond_r, s.min_tet_r, s.min_ref_V_rel_at_min, s.tets,
                  s.inverted, s.r01, s.r001, s.tet_energy, s.bond_energy, s.max_bond_factor,
                  s.max_tet_factor, 2 * std::sqrt(b.density / s.max_total_cur),
                  2 * std::sqrt(b.density / s.max_guard));
      break;
    }
    if (sim.step() % every == 0 || sim.time() >= scene.time.end_time * (1 - 1e-12)) {
      Stats s = measure(b, true);
      const Energies en = sim.energies();
      std::printf(
          "%lld %.4g %.4f %.3g %.3g %zu %zu %zu %zu %.4g %.4g %.3g %.3g %.3g %.3g %.4g %.4g\n",
          sim.step(), sim.time(), s.min_bond_r, s.min_tet_r, s.min_ref_V_rel_at_min, s.tets,
          s.inverted, s.r01, s.r001, s.tet_energy, s.bond_energy, s.max_bond_factor,
          s.max_tet_factor, 2 * std::sqrt(b.density / s.max_total_cur),
          2 * std::sqrt(b.density / s.max_guard), en.kinetic, en.strain);
      std::fflush(stdout);
    }
    if (sim.time() >= scene.time.end_time * (1 - 1e-12)) break;
  }
  std::printf("# dt used %.4g\n", dt);
}
