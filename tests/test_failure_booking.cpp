// The damage step's energy booking (bodies/bond_failure.hpp) evaluates only the bonds and sets
// that the failures switch off. Proven here against the plain oracle, the body's whole strain
// energy (every point's own family through the reference point kernel) before and after the
// failures, both read at the booking displacement u - half_drift v: on perturbed, already
// damaged lattices and jittered clouds, 2D and 3D (families of more than 64 members too: the
// bit rows span words), under both damage rules and both force forms, with a Seth-Hill measure
// and the inversion penalty, with many bonds failing at once (sets switched off by several
// failures, booked once) and with a few (the sets reached only through a failing edge between
// two members under all_edges); the same bonds fail as update_bond_failure fails; and the result
// is the same bit for bit at 1 and 2 threads.
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/damage.hpp"
#include "bodies/point_kernel.hpp"
#include "kernel_comparison.hpp"

using ckpd::Body;
using ckpd::DamageRule;
using ckpd::Vec3;

namespace {

double whole_strain_energy(const Body& body) {
  ckpd::FamilyScratch scratch;
  double e = 0;
  for (std::size_t i = 0; i < body.size(); ++i)
    e += body.volume[i] * ckpd::evaluate_point(body, i, scratch).strain_energy_density();
  return e;
}

// The critical stretch at which about `count` of the intact bonds (each counted once) are over
// it: just below the count-th largest stretch.
double stretch_failing_about(const Body& body, std::size_t count) {
  std::vector<double> s;
  for (std::size_t i = 0; i < body.size(); ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::uint32_t j = body.family.neighbour[k];
      if (j > i && body.bond_intact[k])
        s.push_back(ckpd::bond_stretch(body.reference_position[j] - body.reference_position[i],
                                       body.displacement[j] - body.displacement[i]));
    }
  std::sort(s.begin(), s.end());
  return 0.5 * (s[s.size() - count] + s[s.size() - count - 1]);
}

struct BookingScene {
  kernel_comparison::Scene scene;
  double strain_measure = 0.5;
  double inversion_penalty = 0;
};

}  // namespace

TEST_CASE("failure booking equals the drop of the whole body's strain energy", "[damage]") {
  using namespace kernel_comparison;
  ThreadCountGuard guard;
  const std::vector<BookingScene> scenes = {
      {{"2D lattice, nu=0.4 (C2>0)", 2, 0.4, 0.0, 13, 11, 1}},
      {{"2D jittered cloud, nu=0.3 (C2<0), log measure", 2, 0.3, 0.2, 12, 12, 1}, 0.0},
      {{"2D lattice, m=5.2 (families over 64)", 2, 0.4, 0.0, 16, 15, 1, false, 5.2}},
      {{"3D lattice, nu=0.3", 3, 0.3, 0.0, 7, 6, 5}},
      {{"3D jittered cloud, triangles too, inversion penalty", 3, 0.25, 0.2, 6, 6, 5, true},
       0.5,
       1e9},
  };
  for (const BookingScene& bs : scenes) {
    const Scene& s = bs.scene;
    for (const DamageRule rule : {DamageRule::centre_bonds, DamageRule::all_edges})
      for (const ckpd::ForceForm form :
           {ckpd::ForceForm::own_family, ckpd::ForceForm::energy_consistent})
        for (const bool few : {false, true}) {
          std::mt19937 rng(47);
          Body body = ckpd::make_body(
              block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m));
          body.damage_rule = rule;
          body.force_form = form;
          body.strain_measure = bs.strain_measure;
          body.inversion_penalty = bs.inversion_penalty;
          perturb(body, 0.04, rng);
          fail_bonds(body, 0.05, rng);  // damage before this step: sets already off stay off
          std::uniform_real_distribution<double> u(-0.3 * kDx, 0.3 * kDx);
          for (Vec3& v : body.velocity) v = Vec3(u(rng), u(rng), s.dimension == 3 ? u(rng) : 0.0);
          // Many: a few per cent of the intact bonds are over it. Few: three.
          body.critical_stretch = few ? stretch_failing_about(body, 3) : 0.03;
          const double half_drift = 0.37;

          Body at_booking = body;
          for (std::size_t i = 0; i < body.size(); ++i)
            at_booking.displacement[i] -= half_drift * body.velocity[i];
          const double before = whole_strain_energy(at_booking);
          Body decided = body;
          const std::size_t expected_failures = ckpd::update_bond_failure(decided);

          std::vector<ckpd::FailureUpdate> updates;
          for (const int threads : {1, 2}) {
            omp_set_num_threads(threads);
            Body b = body;
            updates.push_back(ckpd::fail_overstretched_bonds(b, half_drift));
            CHECK(b.bond_intact == decided.bond_intact);
            CHECK(b.displacement == body.displacement);  // the end-of-step state is put back
          }
          at_booking.bond_intact = decided.bond_intact;
          const double after = whole_strain_energy(at_booking);
          INFO(s.label << ", " << ckpd::to_string(rule) << ", " << ckpd::to_string(form)
                       << (few ? ", few" : ", many") << ": " << updates[0].failed
                       << " bonds failed, booked " << updates[0].dissipated << ", oracle "
                       << before - after << " of " << before);
          if (few)
            REQUIRE(expected_failures == 3);
          else
            REQUIRE(expected_failures > 10);
          CHECK(updates[0].failed == expected_failures);
          CHECK(std::abs(updates[0].dissipated - (before - after)) <= 1e-12 * before);
          CHECK(updates[1].failed == updates[0].failed);
          CHECK(updates[1].dissipated == updates[0].dissipated);  // bit for bit
        }
  }
}

TEST_CASE("the damage step fails exactly the bonds over the critical stretch, at its rounding",
          "[damage]") {
  // The damage step passes over bonds whose squared length is clearly below the critical one
  // (bond_failure.hpp, stretch_screen) before the exact test. With the critical stretch set to
  // a bond's own computed stretch, or one rounding step below it, the bonds that fail are
  // still those the exact test alone fails (update_bond_failure): that bond only in the second.
  using namespace kernel_comparison;
  std::mt19937 rng(5);
  const Scene s{"3D lattice", 3, 0.3, 0.0, 6, 6, 5};
  Body body =
      ckpd::make_body(block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m));
  perturb(body, 0.04, rng);
  const double sc = stretch_failing_about(body, 5);
  // The smallest computed stretch above sc: the bond that sits on the threshold.
  double edge = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < body.size(); ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::uint32_t j = body.family.neighbour[k];
      const double st = ckpd::bond_stretch(body.reference_position[j] - body.reference_position[i],
                                           body.displacement[j] - body.displacement[i]);
      if (st > sc) edge = std::min(edge, st);
    }
  for (const double critical : {edge, std::nextafter(edge, 0.0)}) {
    Body decided = body, stepped = body;
    decided.critical_stretch = stepped.critical_stretch = critical;
    const std::size_t expected = ckpd::update_bond_failure(decided);
    const ckpd::FailureUpdate update = ckpd::fail_overstretched_bonds(stepped, 0.0);
    INFO("critical stretch " << critical << " (edge " << edge << ")");
    CHECK(update.failed == expected);
    CHECK(stepped.bond_intact == decided.bond_intact);
    CHECK(expected == (critical == edge ? 4u : 5u));
  }
}
