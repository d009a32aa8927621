// History quantities chosen in the case: the contact force between two colliding discs
// integrates (trapezoid over the rows, as velocity Verlet integrates it) to each disc's
// momentum change; the reaction force on the grips of a stretched bar is E_eff A strain; per
// body columns are what they say; bad names are listed with the known ones.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <sstream>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// Columns by name, one vector per column.
std::map<std::string, std::vector<double>> read_history(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string n; std::getline(header, n, ',');) names.push_back(n);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string v;
    for (std::size_t k = 0; std::getline(row, v, ','); ++k)
      columns[names.at(k)].push_back(std::stod(v));
  }
  return columns;
}

// nu = 1/3 in plane stress: C2 = 0 and the internal forces sum to zero exactly, so each disc's
// momentum changes by its contact force alone.
const char* kDiscs = R"(# SI units
materials:
  m: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3333333333333333}
bodies:
  - {name: left, material: m, dimension: 2, geometry: {type: sphere, center: [-0.0026, 0.0003],
     radius: 0.0025}, spacing: 0.0005, horizon_ratio: 3.015}
  - {name: right, material: m, dimension: 2, geometry: {type: sphere, center: [0.0026, 0],
     radius: 0.0025}, spacing: 0.0005, horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: left, value: [10, 0]}
  - {type: initial_velocity, body: right, value: [-10, 0]}
contact: {stiffness: 1.0e12}
time: {end: 6.0e-5}
output:
  history_interval: 1
  history:
    - {quantity: contact_force, bodies: [left, right]}
    - {quantity: contact_force, bodies: [right, left]}
    - {quantity: contact_energy, bodies: [left, right]}
    - {quantity: momentum, body: left}
    - {quantity: mean_velocity, body: right, name: v_right}
    - {quantity: kinetic_energy, body: left}
    - {quantity: strain_energy, body: left}
    - {quantity: centre_of_mass, body: left}
    - {quantity: broken_bonds, body: left}
    - {quantity: fragments, body: left}
)";

}  // namespace

TEST_CASE("the contact force history of a collision integrates to the momentum change",
          "[history][contact]") {
  const auto dir = fresh_dir("history-contact");
  const std::string file = write_file(dir / "case.yaml", kDiscs);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  auto h = read_history(dir / "out" / "history.csv");
  const auto& t = h.at("time");
  const auto& fx = h.at("contact_force_left_right_x");
  const auto& fy = h.at("contact_force_left_right_y");
  const auto& px = h.at("momentum_left_x");
  const auto& py = h.at("momentum_left_y");
  REQUIRE(t.size() > 100);
  double impulse_x = 0, impulse_y = 0, peak = 0, worst_pair = 0, energy_peak = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double dt = t[k] - t[k - 1];
    impulse_x += 0.5 * dt * (fx[k] + fx[k - 1]);
    impulse_y += 0.5 * dt * (fy[k] + fy[k - 1]);
  }
  for (std::size_t k = 0; k < t.size(); ++k) {
    peak = std::max(peak, std::abs(fx[k]));
    // Newton's third law between the two histories.
    worst_pair = std::max(worst_pair, std::abs(fx[k] + h.at("contact_force_right_left_x")[k]));
    energy_peak = std::max(energy_peak, h.at("contact_energy_left_right")[k]);
    CHECK(h.at("contact_energy_left_right")[k] == h.at("contact")[k]);
  }
  const double dpx = px.back() - px.front(), dpy = py.back() - py.front();
  INFO("impulse " << impulse_x << ", " << impulse_y << " N s; momentum change " << dpx << ", "
                  << dpy << " N s; peak force " << peak << " N");
  CHECK(peak > 0);
  CHECK(energy_peak > 0);
  CHECK(dpx < 0);  // the left disc is pushed back
  CHECK(impulse_x == Approx(dpx).epsilon(1e-6));
  CHECK(std::abs(impulse_y - dpy) < 1e-6 * std::abs(dpx));
  CHECK(worst_pair < 1e-6 * peak);
  // Per-body columns against the default ones and against each other.
  const auto& v = h.at("v_right_x");
  CHECK(v.front() == Approx(-10).epsilon(1e-12));
  CHECK(v.back() > 0);  // rebounded
  for (std::size_t k = 0; k < t.size(); ++k) {
    CHECK(h.at("kinetic_energy_left")[k] <= h.at("kinetic")[k] * (1 + 1e-12));
    CHECK(h.at("strain_energy_left")[k] <= h.at("strain")[k] * (1 + 1e-12) + 1e-300);
    CHECK(h.at("broken_bonds_left")[k] == 0);
    CHECK(h.at("fragments_left")[k] == 1);
  }
  CHECK(h.at("centre_of_mass_left_x").front() == Approx(-0.0026).margin(1e-5));
  CHECK(h.at("kinetic_energy_left").front() == Approx(h.at("kinetic").front() / 2).epsilon(1e-12));
}

TEST_CASE("bad history quantities are rejected, listing what is known", "[history]") {
  const auto dir = fresh_dir("history-bad");
  auto run = [&](const std::string& from, const std::string& to) {
    std::string text = kDiscs;
    text.replace(text.find(from), from.size(), to);
    return run_ckpd("run " + write_file(dir / "case.yaml", text) + " --quiet --out " +
                    (dir / "out").string());
  };
  CommandResult r = run("{quantity: momentum, body: left}", "{quantity: momentun, body: left}");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("did you mean 'momentum'") != std::string::npos);
  CHECK(r.output.find("known: momentum, centre_of_mass") != std::string::npos);
  r = run("{quantity: momentum, body: left}", "{quantity: momentum, body: lft}");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("did you mean 'left'") != std::string::npos);
  CHECK(r.output.find("bodies: left, right") != std::string::npos);
  r = run("{quantity: contact_force, bodies: [left, right]}",
          "{quantity: contact_force, bodies: [left, left]}");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("two different bodies") != std::string::npos);
}

namespace {

// A 2D strip 40 x 10 points between two grips 3 points (one horizon) long: the left grip is
// held, the right one pulled along x smoothly and slowly (v = 0.2 sin^2(pi t / 400 us) m/s, a
// table of 17 rows; 10 wave transits of the bar), each only along x so the grips do not hold
// the strip's contraction; then held for 100 us.
const char* kBar = R"(# SI units
materials:
  m: {density: 1000, youngs_modulus: 1.0e9, poisson_ratio: 0.3333333333333333}
bodies:
  - {name: bar, material: m, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.040, 0.010]},
     spacing: 0.001, horizon_ratio: 3.015, constants: calibrated}
conditions:
  - {type: velocity, body: bar, region: {type: box, min: [0, 0], max: [0.003, 0.010]},
     components: [x], value: [0, 0]}
  - {type: velocity, body: bar, region: {type: box, min: [0.037, 0], max: [0.040, 0.010]},
     components: [x],
     value: {table: [[0, 0, 0], [2.5e-05, 0.00761205, 0], [5e-05, 0.0292893, 0], [7.5e-05, 0.0617317, 0], [0.0001, 0.1, 0], [0.000125, 0.138268, 0], [0.00015, 0.170711, 0], [0.000175, 0.192388, 0], [0.0002, 0.2, 0], [0.000225, 0.192388, 0], [0.00025, 0.170711, 0], [0.000275, 0.138268, 0], [0.0003, 0.1, 0], [0.000325, 0.0617317, 0], [0.00035, 0.0292893, 0], [0.000375, 0.00761205, 0], [0.0004, 2.99952e-33, 0]]}}
time: {end: 5.0e-4}
output:
  history_interval: 20
  history:
    - {quantity: reaction_force, body: bar, region: {type: box, min: [0.037, 0], max: [0.040, 0.010]}, name: pull}
    - {quantity: reaction_force, body: bar, region: {type: box, min: [0, 0], max: [0.003, 0.010]}, name: hold}
    - {quantity: reaction_force, body: bar, region: {type: box, min: [0.015, 0], max: [0.025, 0.010]}, name: free}
)";

// The bar's text for a width of `rows` points (kBar has 10).
std::string bar_case(int rows) {
  std::string text = kBar;
  const std::string from = "0.010]",
                    to = "0." + std::string(rows < 100 ? "0" : "") + std::to_string(rows) + "]";
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  // One frame at the end: the strain is measured in the middle of the bar from it.
  return text + "  field_interval: 1000000\n  fields: [reference_position, displacement, stress]\n";
}

std::vector<double> read_dataset(hid_t file, const std::string& path) {
  const hid_t set = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  REQUIRE(set >= 0);
  const hid_t space = H5Dget_space(set);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  REQUIRE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0);
  H5Sclose(space);
  H5Dclose(set);
  return v;
}

// du_x/dX by least squares over the points with 12 mm <= X <= 28 mm, from the last frame.
double mid_strain(const std::filesystem::path& out) {
  const hid_t file =
      H5Fopen((out / "fields" / "frame_000001.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const auto X = read_dataset(file, "/body_0/reference_position");
  const auto u = read_dataset(file, "/body_0/displacement");
  H5Fclose(file);
  double sx = 0, su = 0, sxx = 0, sxu = 0, n = 0;
  for (std::size_t i = 0; i < X.size() / 3; ++i) {
    const double x = X[3 * i], ux = u[3 * i];
    if (x < 0.012 || x > 0.028) continue;
    sx += x;
    su += ux;
    sxx += x * x;
    sxu += x * ux;
    n += 1;
  }
  return (n * sxu - sx * su) / (n * sxx - sx * sx);
}

// The mean sigma_xx (the per-point stress field, volume-weighted; all points have one volume)
// over the points with 12 mm <= X <= 28 mm, from the last frame.
double mid_stress(const std::filesystem::path& out) {
  const hid_t file =
      H5Fopen((out / "fields" / "frame_000001.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const auto X = read_dataset(file, "/body_0/reference_position");
  const auto sigma = read_dataset(file, "/body_0/stress");
  H5Fclose(file);
  REQUIRE(sigma.size() == 2 * X.size());
  double sum = 0, n = 0;
  for (std::size_t i = 0; i < X.size() / 3; ++i) {
    if (X[3 * i] < 0.012 || X[3 * i] > 0.028) continue;
    sum += sigma[6 * i];
    n += 1;
  }
  return sum / n;
}

// The reaction (averaged over the last 100 us, held) over E W strain, strain from the middle.
double bar_ratio(int rows, double& strain, double& pull, double& hold, double& pull_y, double& free,
                 double& stress) {
  const auto dir = fresh_dir("history-reaction");
  const std::string file = write_file(dir / "case.yaml", bar_case(rows));
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  auto h = read_history(dir / "out" / "history.csv");
  const auto& t = h.at("time");
  pull = hold = pull_y = free = 0;
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    free = std::max(free, std::abs(h.at("free_x")[k]) + std::abs(h.at("free_y")[k]));
    if (t[k] < 4.0e-4) continue;
    pull += h.at("pull_x")[k];
    pull_y += h.at("pull_y")[k];
    hold += h.at("hold_x")[k];
    ++n;
  }
  REQUIRE(n > 3);
  pull /= n;
  hold /= n;
  pull_y /= n;
  strain = mid_strain(dir / "out");
  stress = mid_stress(dir / "out");
  return pull / (1.0e9 * 0.001 * rows * strain);
}

}  // namespace

TEST_CASE("the reaction force of a slowly stretched bar is E_eff A strain", "[history][reaction]") {
  // Calibrated constants: an interior point has the continuum's bulk and P-wave moduli, so the
  // uniaxial-stress modulus along a lattice axis is E: the patch-test ratio is 1. The rows
  // whose families a free surface cuts are softer (the peridynamic skin), so a bar of width W
  // carries (1 - a / W) of that; two widths give a and the interior ratio 1 - a / infinity.
  double strain = 0, pull = 0, hold = 0, pull_y = 0, free = 0, stress = 0;
  const double narrow = bar_ratio(10, strain, pull, hold, pull_y, free, stress);
  INFO("10 rows: pull " << pull << " N/m, hold " << hold << " N/m, strain " << strain << ", ratio "
                        << narrow << "; mean stress x W " << stress * 0.010 << " N/m");
  // The stress field carries the force through the bar: its mean over the middle times the
  // width is the grips' reaction (the virial of a section is the force it transmits).
  CHECK(stress * 0.010 == Approx(pull).epsilon(0.01));
  CHECK(strain > 5e-4);
  CHECK(pull > 0);
  CHECK(hold == Approx(-pull).epsilon(0.01));  // quasi-static: the grips balance
  CHECK(std::abs(pull_y) < 1e-9 * pull);       // the grips hold x only
  CHECK(free < 1e-9 * pull);                   // free points need no holding
  const double wide = bar_ratio(20, strain, pull, hold, pull_y, free, stress);
  CHECK(stress * 0.020 == Approx(pull).epsilon(0.01));
  const double interior = 2 * wide - narrow;  // r(W) = 1 - a / W at W = 10 and 20 rows
  INFO("20 rows: ratio " << wide << "; interior (W -> infinity) " << interior);
  CHECK(narrow < wide);
  CHECK(wide < 1);
  CHECK(interior == Approx(1.0).epsilon(0.01));
}
