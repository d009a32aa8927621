#include "src/cli/patch_test_command.hpp"

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "bodies/patch_test.hpp"

namespace ckpd {

namespace {
struct PatchTestOptions {
  int dimension = 3;
  double m = 3.015;
  double youngs_modulus = 210e9;
  double poisson_ratio = 0.3;
  std::string plane = "stress";
  bool calibrated = false;
};
}  // namespace

void add_patch_test_command(CLI::App& app) {
  auto opt = std::make_shared<PatchTestOptions>();
  CLI::App* cmd = app.add_subcommand(
      "patch-test",
      "Stiffness error of a lattice discretisation: N1, N2, N3 of an interior point and its "
      "strain-energy density over the continuum's for volumetric, shear and uniaxial strain");
  cmd->add_option("--dim", opt->dimension, "dimension, 2 or 3")->check(CLI::IsMember({2, 3}));
  cmd->add_option("--m", opt->m, "horizon ratio delta/dx")->check(CLI::Range(1.0, 12.0));
  cmd->add_option("--E", opt->youngs_modulus, "Young's modulus [Pa]");
  cmd->add_option("--nu", opt->poisson_ratio, "Poisson's ratio");
  cmd->add_option("--plane", opt->plane, "2D only: stress or strain")
      ->check(CLI::IsMember({"stress", "strain"}));
  cmd->add_flag("--calibrated", opt->calibrated,
                "also print the calibrated constants (body key `constants: calibrated`) and "
                "the ratios they give");
  cmd->callback([opt]() {
    const PlaneMode plane =
        opt->dimension == 2 ? plane_mode_from_string(opt->plane) : PlaneMode::none;
    const PatchTestResult r =
        run_patch_test(opt->dimension, opt->m, opt->youngs_modulus, opt->poisson_ratio, plane);
    nlohmann::ordered_json j;
    j["dimension"] = opt->dimension;
    j["m"] = opt->m;
    j["E"] = opt->youngs_modulus;
    j["nu"] = opt->poisson_ratio;
    if (opt->dimension == 2) j["plane"] = opt->plane;
    j["N1"] = r.n1;
    j["N2"] = r.n2;
    j["N3"] = r.n3;
    j["ratio"] = {{"volumetric", r.volumetric}, {"shear", r.shear}, {"uniaxial", r.uniaxial}};
    if (opt->calibrated) {
      // Constants of the unit lattice (spacing 1, horizon m), and their ratio to the analytic
      // ones (null where the analytic constant is 0).
      const InteractionConstants plain = interaction_constants(opt->dimension, opt->youngs_modulus,
                                                               opt->poisson_ratio, plane, opt->m);
      const InteractionConstants cal = calibrated_constants(opt->dimension, opt->youngs_modulus,
                                                            opt->poisson_ratio, plane, opt->m, 1.0);
      const PatchTestResult rc = run_patch_test(opt->dimension, opt->m, opt->youngs_modulus,
                                                opt->poisson_ratio, plane, cal);
      auto scale = [](double c, double p) {
        return p != 0 ? nlohmann::ordered_json(c / p) : nlohmann::ordered_json(nullptr);
      };
      const char* other = opt->dimension == 2 ? "C2" : "C3";
      const double cal_n = opt->dimension == 2 ? cal.c2 : cal.c3;
      const double plain_n = opt->dimension == 2 ? plain.c2 : plain.c3;
      nlohmann::ordered_json c;
      c["constants"] = {{"C1", cal.c1}, {other, cal_n}};
      c["analytic_constants"] = {{"C1", plain.c1}, {other, plain_n}};
      c["scale"] = {{"C1", scale(cal.c1, plain.c1)}, {other, scale(cal_n, plain_n)}};
      c["ratio"] = {{"volumetric", rc.volumetric}, {"shear", rc.shear}, {"uniaxial", rc.uniaxial}};
      j["calibrated"] = c;
    }
    std::cout << j.dump(2) << '\n';
  });
}

}  // namespace ckpd
