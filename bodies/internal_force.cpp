#include "bodies/internal_force.hpp"

#include <cmath>

namespace ckpd {

PointResult evaluate_point(const Body& body, std::size_t i, FamilyScratch& s) {
  const bool pairs = body.has_pairs(), triples = body.has_triples();
  s.load(body, i, body.damage_enabled, pairs || triples);
  const double c1 = body.constants.c1, c2 = body.constants.c2, c3 = body.constants.c3;
  const double dv1 = body.dv1[i], dv2 = body.dv2[i], dv3 = body.dv3[i];
  const double degenerate = body.degenerate_fraction;
  // Penalty factors in units of C: 2 F |C| / C (zero when off).
  const double pen2 = c2 != 0 ? 2 * body.inversion_penalty * (c2 > 0 ? 1.0 : -1.0) : 0.0;
  const double pen3 = c3 != 0 ? 2 * body.inversion_penalty * (c3 > 0 ? 1.0 : -1.0) : 0.0;
  const bool planar = body.dimension == 2;
  std::uint32_t inverted = 0;
  PointResult r;
  Vec3 b = Vec3::Zero();
  double w1 = 0, w2 = 0, w3 = 0;

  for (std::size_t a = 0; a < s.size(); ++a) {
    const double L = s.length[a], l = s.cur[a].norm();
    b += (c1 * dv1 * (1 / L - 1 / l)) * s.cur[a];
    const double stretch = l / L - 1;
    w1 += 0.5 * c1 * L * stretch * stretch * dv1;
  }

  if (pairs) {
    s.for_each_pair([&](std::size_t a, std::size_t c) {
      const Vec3 ref_area = s.ref[a].cross(s.ref[c]);
      const double A = ref_area.norm();
      if (A <= degenerate * s.length[a] * s.length[c]) return;
      const Vec3 p = s.cur[a], q = s.cur[c];
      const Vec3 area = p.cross(q);
      const double an = area.norm();
      // (1/A - 1/|a|) a, written so that a collapsed triangle (|a| = 0) gives a finite force.
      double f = 1 / A - (an > 0 ? 1 / an : 0.0);
      const double e = an / A - 1;
      double en = A * e * e;
      // In a plane the sign of the z component is the orientation (rotation-invariant there).
      if (planar && area.z() * ref_area.z() < 0) {
        ++inverted;
        // Penalty 2 F |C2| |a|: d|a|/dx adds pen2 a/|a| to (|a|/A - 1) a/|a|.
        f += pen2 / an;
        en += 2 * pen2 * an;
      }
      b += (2 * c2 * dv2 * f) * (q - p).cross(area);
      w2 += c2 * en * dv2;  // 2 orders x psi2
    });
  }

  if (triples) {
    s.for_each_triple([&](std::size_t a, std::size_t c, std::size_t d) {
      const Vec3 P = s.ref[a], Q = s.ref[c], R = s.ref[d];
      const double signed_V = P.dot(Q.cross(R)), V = std::abs(signed_V);
      if (V <= degenerate * s.length[a] * s.length[c] * s.length[d]) return;
      const Vec3 p = s.cur[a], q = s.cur[c], r = s.cur[d];
      const Vec3 qr = q.cross(r), rp = r.cross(p), pq = p.cross(q);
      const double v = p.dot(qr), av = std::abs(v);
      const double sign_v = v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
      // (1/|V| - 1/|v|) v = v/|V| - sign(v)
      double factor = v / V - sign_v;
      const double e = av / V - 1;
      double en = V * e * e;
      if (v * signed_V < 0) {
        ++inverted;
        // Penalty 2 F |C3| |v|: its derivative in v is C3 pen3 sign(v).
        factor += pen3 * sign_v;
        en += 2 * pen3 * av;
      }
      b += (6 * c3 * dv3 * factor) * (qr + rp + pq);
      w3 += 3 * c3 * en * dv3;  // 6 orders x psi3
    });
  }
  r.force_density = b;
  r.w1 = w1;
  r.w2 = w2;
  r.w3 = w3;
  r.inverted = inverted;
  return r;
}

void compute_internal_force(Body& body, bool with_energy) {
  const std::size_t n = body.size();
#pragma omp parallel
  {
    FamilyScratch scratch;
    // Dynamic chunks: points near surfaces and cracks have far fewer interactions.
#pragma omp for schedule(dynamic, 32)
    for (std::size_t i = 0; i < n; ++i) {
      const PointResult r = evaluate_point(body, i, scratch);
      body.force_density[i] = r.force_density;
      if (with_energy) body.strain_energy_density[i] = r.strain_energy_density();
    }
  }
}

double strain_energy(const Body& body) {
  double e = 0;
  for (std::size_t i = 0; i < body.size(); ++i) e += body.strain_energy_density[i] * body.volume[i];
  return e;
}

}  // namespace ckpd
