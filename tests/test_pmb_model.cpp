// The PMB bond model (bodies/pmb_model.hpp, `model: pmb`): its bond force against the closed
// form c s along the bond, its energy c L s^2 / 2 and linearisation against finite differences,
// a PMB body against the bond-only CKPD body with C1 = c, and the LAMMPS comparison case run with
// a pmb material against the CKPD material it replaces.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "bodies/damage.hpp"
#include "bodies/force_model_kernels.hpp"
#include "bodies/pmb_model.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "body_fixtures.hpp"
#include "run_helpers.hpp"

namespace {

using ckpd::PmbModel;
using ckpd::Vec3;

}  // namespace

TEST_CASE("PMB bond force is c s along the bond and its energy c L s^2 / 2", "[pmb_model]") {
  const PmbModel model{1.6863e22, 5e-4};
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 P = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 p = P + 3e-5 * Vec3(u(rng), u(rng), u(rng));
    const double L = P.norm(), l = p.norm(), s = (l - L) / L;
    const ckpd::SetTerm<2> t = model.bond_term(P, p);
    // Force density per unit neighbour volume on the first end: c s towards the second.
    CHECK((t.force[0] - model.c * s * p / l).norm() <= 1e-12 * model.c * std::abs(s));
    CHECK((t.force[0] + t.force[1]).norm() == 0);
    CHECK(t.energy == Approx(model.c * L * s * s / 2).epsilon(1e-10));
    // Minus the energy's gradient at the second end, by central differences.
    const double h = 1e-9;
    for (int d = 0; d < 3; ++d) {
      Vec3 plus = p, minus = p;
      plus[d] += h;
      minus[d] -= h;
      const double g =
          (model.bond_term(P, plus).energy - model.bond_term(P, minus).energy) / (2 * h);
      CHECK(t.force[1][d] == Approx(-g).epsilon(1e-6).margin(1e-6 * t.force[0].norm()));
    }
    // Linearisation at the reference state against the finite-difference Jacobian.
    const ckpd::SetLinearisation<2> lin = model.bond_linearisation(P);
    const double hl = 1e-8;
    for (int d = 0; d < 3; ++d) {
      Vec3 plus = P, minus = P;
      plus[d] += hl;
      minus[d] -= hl;
      const Vec3 column =
          (model.bond_term(P, plus).force[0] - model.bond_term(P, minus).force[0]) / (2 * hl);
      CHECK((column - lin.block(0, 1).col(d)).norm() <= 1e-7 * lin.block(0, 1).norm());
    }
  }
  CHECK(!model.bond_fails(5e-4));
  CHECK(model.bond_fails(5.0001e-4));
}

TEST_CASE("a PMB body gives the bond-only CKPD body's forces, energies and failures",
          "[pmb_model]") {
  // nu = 1/4: CKPD has bonds only, with C1 = 12 E / (pi delta^4) = c.
  const double dx = 5e-4, m = 3.0002;
  const ckpd::InteractionConstants k =
      ckpd::interaction_constants(3, 2.2e10, 0.25, ckpd::PlaneMode::none, m * dx);
  REQUIRE(k.c2 == 0);
  REQUIRE(k.c3 == 0);
  ckpd::BodyDefinition d = ckpd_test::lattice_block(3, 9, 8, 7, dx, m, k, 2200);
  d.critical_stretch = 2e-3;
  ckpd::Body ckpd_body = ckpd::make_body(d);
  d.model = &ckpd::kernels_of<PmbModel>();
  d.constants = {k.c1, 0, 0};
  ckpd::Body pmb_body = ckpd::make_body(d);
  REQUIRE(pmb_body.model != ckpd_body.model);
  CHECK(pmb_body.stiffness_bound == ckpd_body.stiffness_bound);
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t i = 0; i < ckpd_body.size(); ++i) {
    const Vec3 du = 3e-3 * dx * Vec3(u(rng), u(rng), u(rng));
    ckpd_body.displacement[i] = pmb_body.displacement[i] = du;
    ckpd_body.velocity[i] = pmb_body.velocity[i] = 1e3 * du;
  }
  const ckpd::FailureUpdate f1 = ckpd::fail_overstretched_bonds(ckpd_body, 1e-8);
  const ckpd::FailureUpdate f2 = ckpd::fail_overstretched_bonds(pmb_body, 1e-8);
  REQUIRE(f1.failed > 0);
  CHECK(f2.failed == f1.failed);
  CHECK(f2.dissipated == f1.dissipated);
  CHECK(pmb_body.bond_intact == ckpd_body.bond_intact);
  ckpd::compute_internal_force_symmetric(ckpd_body, true);
  ckpd::compute_internal_force_symmetric(pmb_body, true);
  CHECK(pmb_body.force_density == ckpd_body.force_density);
  CHECK(pmb_body.strain_energy_density == ckpd_body.strain_energy_density);
}

TEST_CASE("the LAMMPS comparison case with a pmb material matches its CKPD material",
          "[pmb_model][cli]") {
  // bench/lammps/pmb_cylinder.yaml uses LAMMPS's micromodulus; here it is set to the C1 that the
  // CKPD material it replaced (E = 2.2355496e10 Pa, nu = 0.25) gives, so the two must agree to
  // round-off: same broken bonds, same energies. 150 of the case's 1000 steps: bonds break from
  // step ~90.
  using namespace ckpd::testing;
  const std::filesystem::path source = CKPD_SOURCE_DIR;
  std::ifstream in(source / "bench/lammps/pmb_cylinder.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string pmb = text.str();
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  pmb = replace(pmb, "file: cylinder_points.csv",
                "file: " + (source / "bench/lammps/cylinder_points.csv").string());
  const double horizon = 0.0015001;
  const double c1 =
      ckpd::interaction_constants(3, 2.2355496e10, 0.25, ckpd::PlaneMode::none, horizon).c1;
  char exact[64];
  std::snprintf(exact, sizeof exact, "%.17g", c1);
  // The material block, whichever model the case file has, becomes each of the two.
  const auto begin = pmb.find("  pmb_glass:\n");
  const auto end = pmb.find("bodies:\n");
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  std::string ckpd_case = pmb;
  ckpd_case.replace(begin, end - begin,
                    "  pmb_glass: {density: 2200, youngs_modulus: 2.2355496e10, poisson_ratio: "
                    "0.25, critical_stretch: 0.0005}\n");
  pmb.replace(begin, end - begin,
              std::string("  pmb_glass: {model: pmb, density: 2200, micromodulus: ") + exact +
                  ", critical_stretch: 0.0005}\n");
  const auto dir = fresh_dir("pmb-cylinder");
  const std::string steps = " --threads 1 --quiet --set time.steps=150";
  const CommandResult a = run_ckpd("run " + write_file(dir / "pmb.yaml", pmb) + " --out " +
                                   (dir / "pmb").string() + steps);
  const CommandResult b = run_ckpd("run " + write_file(dir / "ckpd.yaml", ckpd_case) + " --out " +
                                   (dir / "ckpd").string() + steps);
  INFO(a.output << b.output);
  REQUIRE(a.exit_code == 0);
  REQUIRE(b.exit_code == 0);
  const auto sp = read_json(dir / "pmb" / "summary.json");
  const auto sc = read_json(dir / "ckpd" / "summary.json");
  CHECK(sp["bodies"][0]["kernel"]["model"] == "pmb");
  CHECK(sc["bodies"][0]["kernel"]["model"] == "ckpd");
  CHECK(sp["broken_bonds"].get<long>() > 0);
  CHECK(sp["broken_bonds"] == sc["broken_bonds"]);
  for (const char* key : {"kinetic", "strain", "contact", "external_work", "dissipated"}) {
    const double x = sp["energy"][key], y = sc["energy"][key];
    INFO(key << ": pmb " << x << ", ckpd " << y);
    CHECK(std::abs(x - y) <= 1e-12 * std::max(std::abs(x), std::abs(y)));
  }
}

TEST_CASE("a pmb material needs its micromodulus and refuses CKPD's keys and calibration",
          "[pmb_model][cli]") {
  using namespace ckpd::testing;
  const std::string base = R"(# a small 3D block, SI units
materials:
  glass: {model: pmb, density: 2200, MATERIAL}
bodies:
  - name: block
    material: glass
    geometry: {type: box, min: [0, 0, 0], max: [0.004, 0.004, 0.004]}
    spacing: 0.001
    horizon_ratio: 3.015BODY
time: {steps: 2}
)";
  auto run = [&](const std::string& material, const std::string& body) {
    std::string text = base;
    text.replace(text.find("MATERIAL"), 8, material);
    text.replace(text.find("BODY"), 4, body);
    const auto dir = fresh_dir("pmb-keys");
    return run_ckpd("run " + write_file(dir / "case.yaml", text) + " --quiet --out " +
                    (dir / "out").string());
  };
  const CommandResult good = run("micromodulus: 1e22, critical_stretch: 0.001", "");
  INFO(good.output);
  CHECK(good.exit_code == 0);
  const CommandResult missing = run("critical_stretch: 0.001", "");
  CHECK(missing.exit_code == 2);
  CHECK(missing.output.find("missing required key 'micromodulus'") != std::string::npos);
  const CommandResult ckpd_key = run("micromodulus: 1e22, youngs_modulus: 1e10", "");
  CHECK(ckpd_key.exit_code == 2);
  CHECK(ckpd_key.output.find("materials.glass.youngs_modulus") != std::string::npos);
  CHECK(ckpd_key.output.find("unknown key") != std::string::npos);
  const CommandResult calibrated = run("micromodulus: 1e22", "\n    constants: calibrated");
  INFO(calibrated.output);
  CHECK(calibrated.exit_code == 2);
  CHECK(calibrated.output.find("CKPD option") != std::string::npos);
}
