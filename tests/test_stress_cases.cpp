// The cheapest cases of cases/stress/ through the program: each ends either completed with a
// bounded energy balance error or with status "unstable" and a message naming the failure, and
// never writes a non-finite number into history.csv (docs/STABILITY.md has the full table).
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "run_helpers.hpp"

namespace {

using namespace ckpd::testing;

struct History {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  bool finite = true;
};

History read_history(const std::filesystem::path& path) {
  History h;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) h.columns.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> row;
    for (std::string cell; std::getline(ss, cell, ',');) {
      double v = std::nan("");
      try {
        v = std::stod(cell);  // "nan" and "inf" parse, and are caught below
      } catch (...) {
      }
      if (!std::isfinite(v)) h.finite = false;
      row.push_back(v);
    }
    h.rows.push_back(row);
  }
  return h;
}

double column(const History& h, std::size_t row, const std::string& name) {
  for (std::size_t c = 0; c < h.columns.size(); ++c)
    if (h.columns[c] == name) return h.rows[row][c];
  FAIL("no column " << name);
  return 0;
}

// Worst |balance error| over the rows relative to the energy put in (initial kinetic + strain
// + contact plus the largest |external work|), as scripts/stress_table.py reports it.
double worst_energy_error(const History& h) {
  const double initial = column(h, 0, "kinetic") + column(h, 0, "strain") + column(h, 0, "contact");
  double work = 0, worst = 0;
  for (std::size_t r = 0; r < h.rows.size(); ++r) {
    work = std::max(work, std::abs(column(h, r, "external_work")));
    worst = std::max(worst, std::abs(column(h, r, "balance_error")));
  }
  return worst / (std::abs(initial) + work);
}

void check_case(const std::string& file, const std::string& sets, const std::string& tag) {
  const auto dir = fresh_dir(tag);
  const CommandResult r = run_ckpd("run " + std::string(CKPD_SOURCE_DIR) + "/cases/stress/" + file +
                                   " --out " + dir.string() + " --quiet --threads 1 " + sets);
  INFO(file << " " << sets << ": exit " << r.exit_code << "\n" << r.output);
  REQUIRE((r.exit_code == 0 || r.exit_code == 3));
  const auto summary = read_json(dir / "summary.json");
  const History h = read_history(dir / "history.csv");
  REQUIRE(h.rows.size() >= 2);
  CHECK(h.finite);
  if (r.exit_code == 0) {
    CHECK(summary["status"] == "completed");
    CHECK(worst_energy_error(h) < 0.05);
  } else {
    CHECK(summary["status"] == "unstable");
    CHECK(summary["message"].get<std::string>().find("instability at step") != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace

TEST_CASE("stress cases end completed with bounded energy error or unstable with a message",
          "[stability]") {
  SECTION("two spheres colliding with a contact stiffness of 1e3 GPa") {
    check_case("contact_stiffness.yaml", "--set time.end=2e-5", "stress-contact");
  }
  SECTION("sphere into a brittle plate at 500 m/s") {
    check_case("impact_speed.yaml", "--set conditions.0.value=[0,0,-500] --set time.end=6e-6",
               "stress-impact500");
  }
  SECTION("sphere into a brittle plate at 2000 m/s") {
    check_case("impact_speed.yaml", "--set conditions.0.value=[0,0,-2000] --set time.end=1.5e-6",
               "stress-impact2000");
  }
}
