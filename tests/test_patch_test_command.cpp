#include <catch2/catch.hpp>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

namespace {
std::string run_command(const std::string& cmd) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  REQUIRE(pipe);
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe.get())) out += buf;
  return out;
}
}  // namespace

TEST_CASE("patch-test command prints the MODEL.md reference ratios as JSON", "[cli]") {
  const auto j = nlohmann::json::parse(
      run_command(std::string(CKPD_BINARY) + " patch-test --dim 2 --m 3.015 --E 210e9 --nu 0.3"));
  CHECK(j["N1"] == 28);
  CHECK(j["N2"] == 360);
  CHECK(j["ratio"]["volumetric"].get<double>() == Approx(1.04253).margin(1e-4));
  CHECK(j["ratio"]["shear"].get<double>() == Approx(1.00992).margin(1e-4));
  CHECK(j["ratio"]["uniaxial"].get<double>() == Approx(1.05625).margin(1e-4));
}
