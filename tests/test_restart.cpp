// Checkpoint and restart: N steps plus a restart for N more equals 2N steps bit for bit (cracks
// included); SIGINT leaves a checkpoint; checkpoints of another case or damaged ones are refused.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// A pre-cracked 2D strip pulled apart fast enough that bonds break between steps 40 and 80.
const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.2, fracture_energy: 50}
bodies:
  - name: strip
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.04, 0.02]}
    spacing: 0.001
    horizon_ratio: 3.015
    precracks: [[[0, 0.01], [0.015, 0.01]]]
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0.018], max: [0.04, 0.02]}, value: [0, 2], components: [y]}
  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.04, 0.002]}, value: [0, -2], components: [y]}
time: {steps: 80}
output: {history_interval: 10, checkpoint_interval: 40}
)";

// All datasets and numeric attributes of two checkpoints, compared bit for bit.
void require_identical_checkpoints(const std::filesystem::path& a, const std::filesystem::path& b) {
  const hid_t fa = H5Fopen(a.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t fb = H5Fopen(b.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(fa >= 0);
  REQUIRE(fb >= 0);
  for (const char* attr : {"time", "external_work", "dissipated", "strain_energy"}) {
    double va = 0, vb = 0;
    const hid_t aa = H5Aopen(fa, attr, H5P_DEFAULT), ab = H5Aopen(fb, attr, H5P_DEFAULT);
    H5Aread(aa, H5T_NATIVE_DOUBLE, &va);
    H5Aread(ab, H5T_NATIVE_DOUBLE, &vb);
    H5Aclose(aa);
    H5Aclose(ab);
    INFO(attr);
    CHECK(std::memcmp(&va, &vb, sizeof va) == 0);
  }
  for (const char* name : {"displacement", "velocity", "acceleration", "force_density",
                           "external_force_density", "strain_energy_density", "bond_intact"}) {
    const std::string path = std::string("/body_0/") + name;
    const hid_t da = H5Dopen2(fa, path.c_str(), H5P_DEFAULT);
    const hid_t db = H5Dopen2(fb, path.c_str(), H5P_DEFAULT);
    REQUIRE(da >= 0);
    REQUIRE(db >= 0);
    const hsize_t bytes = H5Dget_storage_size(da);
    REQUIRE(bytes == H5Dget_storage_size(db));
    std::vector<unsigned char> ba(bytes), bb(bytes);
    const hid_t type = H5Dget_type(da);
    H5Dread(da, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ba.data());
    H5Dread(db, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, bb.data());
    H5Tclose(type);
    INFO(name);
    CHECK(ba == bb);
    H5Dclose(da);
    H5Dclose(db);
  }
  H5Fclose(fa);
  H5Fclose(fb);
}

}  // namespace

TEST_CASE("N steps and a restart for N more give the state of 2N steps bit for bit", "[restart]") {
  const auto dir = fresh_dir("restart");
  const std::string file = write_file(dir / "case.yaml", kCase);
  CommandResult r =
      run_ckpd("run " + file + " --quiet --threads 2 --out " + (dir / "full").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto full = read_json(dir / "full" / "summary.json");
  REQUIRE(full["broken_bonds"].get<int>() > 0);  // cracks grew: the bond state matters

  r = run_ckpd("run " + file + " --quiet --threads 2 --set time.steps=40 --out " +
               (dir / "part").string());
  REQUIRE(r.exit_code == 0);
  const auto half = read_json(dir / "part" / "summary.json");
  CHECK(half["broken_bonds"] < full["broken_bonds"]);
  std::filesystem::copy_file(dir / "part" / "checkpoint.h5", dir / "at40.h5");
  r = run_ckpd("run " + file + " --quiet --threads 2 --restart " + (dir / "at40.h5").string() +
               " --out " + (dir / "part").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto resumed = read_json(dir / "part" / "summary.json");
  CHECK(resumed["steps"] == 80);
  CHECK(resumed["restarted_from"]["step"] == 40);
  CHECK(resumed["broken_bonds"] == full["broken_bonds"]);
  CHECK(resumed["energy"] == full["energy"]);
  require_identical_checkpoints(dir / "full" / "checkpoint.h5", dir / "part" / "checkpoint.h5");
  // The continued history has every row once, in order, equal to the uninterrupted run's.
  std::ifstream a(dir / "full" / "history.csv"), b(dir / "part" / "history.csv");
  std::string la, lb;
  int rows = 0;
  while (std::getline(a, la)) {
    REQUIRE(std::getline(b, lb));
    CHECK(la == lb);
    ++rows;
  }
  CHECK_FALSE(std::getline(b, lb));
  CHECK(rows == 10);
}

TEST_CASE("a restart through contact and fragmentation continues bit for bit", "[restart]") {
  // Two discs hit at 60 m/s closing speed and shatter: contact pairs, broken bonds, fragments.
  const char* text = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3, fracture_energy: 20}
bodies:
  - {name: left, material: steel, dimension: 2, geometry: {type: sphere, center: [-0.0101, 0], radius: 0.01},
     spacing: 0.001, horizon_ratio: 3.015}
  - {name: right, material: steel, dimension: 2, geometry: {type: sphere, center: [0.0101, 0], radius: 0.01},
     spacing: 0.001, horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: left, value: [30, 0]}
  - {type: initial_velocity, body: right, value: [-30, 0]}
contact: {stiffness: 1.0e11, radius: 0.0008}
time: {steps: 600}
output: {history_interval: 50, checkpoint_interval: 300}
)";
  const auto dir = fresh_dir("restart-contact");
  const std::string file = write_file(dir / "case.yaml", text);
  REQUIRE(
      run_ckpd("run " + file + " --quiet --threads 2 --out " + (dir / "full").string()).exit_code ==
      0);
  REQUIRE(run_ckpd("run " + file + " --quiet --threads 2 --set time.steps=300 --out " +
                   (dir / "part").string())
              .exit_code == 0);
  std::filesystem::copy_file(dir / "part" / "checkpoint.h5", dir / "at300.h5");
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --threads 2 --restart " + (dir / "at300.h5").string() +
               " --out " + (dir / "part").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto full = read_json(dir / "full" / "summary.json");
  const auto resumed = read_json(dir / "part" / "summary.json");
  CHECK(full["broken_bonds"].get<int>() > 1000);
  CHECK(full["contact"]["point_pairs_in_contact_peak"].get<long long>() > 0);
  CHECK(resumed["energy"] == full["energy"]);
  CHECK(resumed["broken_bonds"] == full["broken_bonds"]);
  require_identical_checkpoints(dir / "full" / "checkpoint.h5", dir / "part" / "checkpoint.h5");
}

TEST_CASE("a restart through frictional contact with a spinning rigid body continues bit for bit",
          "[restart][dem]") {
  // A deformable disc glances off a free rigid disc under linear_dashpot with friction: the
  // springs of the contacting point pairs, the rigid couple and the dissipation cross the
  // checkpoint, which falls mid-contact.
  const char* text = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: left, material: steel, dimension: 2, geometry: {type: sphere, center: [-0.0051, 0.002], radius: 0.005},
     spacing: 0.001, horizon_ratio: 3.015}
  - name: right
    material: steel
    dimension: 2
    rigid: {motion: free, velocity: [-20, 0]}
    geometry: {type: sphere, center: [0.0051, 0], radius: 0.005}
    spacing: 0.001
conditions:
  - {type: initial_velocity, body: left, value: [20, -15]}
contact: {stiffness: 1.0e11, radius: 0.0008, horizon: 0.003, law: linear_dashpot, restitution: 0.5,
          friction: 0.1}
time: {steps: 804}
output: {history_interval: 50, checkpoint_interval: 402}
)";
  // The discs meet at step 397 and slide: step 402 is mid-contact.
  const auto dir = fresh_dir("restart-friction");
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult full_run =
      run_ckpd("run " + file + " --quiet --threads 2 --out " + (dir / "full").string());
  INFO(full_run.output);
  REQUIRE(full_run.exit_code == 0);
  REQUIRE(run_ckpd("run " + file + " --quiet --threads 2 --set time.steps=402 --out " +
                   (dir / "part").string())
              .exit_code == 0);
  const auto at402 = read_json(dir / "part" / "summary.json");
  CHECK(at402["contact"]["point_pairs_in_contact"].get<long long>() > 0);
  CHECK(at402["energy"]["contact_friction"].get<double>() > 0);
  std::filesystem::copy_file(dir / "part" / "checkpoint.h5", dir / "at402.h5");
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --threads 2 --restart " + (dir / "at402.h5").string() +
               " --out " + (dir / "part").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto full = read_json(dir / "full" / "summary.json");
  const auto resumed = read_json(dir / "part" / "summary.json");
  CHECK(full["energy"]["contact_friction"].get<double>() > 0);
  CHECK(full["energy"]["contact_damping"].get<double>() > 0);
  CHECK(std::abs(full["contact"]["rigid_bodies"][0]["angular_velocity"][2].get<double>()) > 0);
  CHECK(resumed["energy"] == full["energy"]);
  CHECK(resumed["contact"]["rigid_bodies"] == full["contact"]["rigid_bodies"]);
  require_identical_checkpoints(dir / "full" / "checkpoint.h5", dir / "part" / "checkpoint.h5");
}

TEST_CASE("SIGINT stops a run with a checkpoint it can continue from", "[restart]") {
  const auto dir = fresh_dir("sigint");
  std::string text = kCase;
  text.replace(text.find("time: {steps: 80}"), 17, "time: {steps: 100000000}");
  const std::string file = write_file(dir / "case.yaml", text);
  const auto out = dir / "out";
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + out.string() +
                                   " & pid=$!; sleep 2; kill -INT $pid; wait $pid; echo exit=$?");
  INFO(r.output);
  CHECK(r.output.find("exit=130") != std::string::npos);
  const auto summary = read_json(out / "summary.json");
  CHECK(summary["status"] == "interrupted");
  REQUIRE(std::filesystem::exists(out / "checkpoint.h5"));
  const long long stopped = summary["steps"];
  const CommandResult more = run_ckpd("run " + file + " --quiet --out " + out.string() +
                                      " --restart " + (out / "checkpoint.h5").string() +
                                      " --set time.steps=" + std::to_string(stopped + 5));
  INFO(more.output);
  CHECK(more.exit_code == 0);
  CHECK(read_json(out / "summary.json")["steps"] == stopped + 5);
}

TEST_CASE("a checkpoint of another case, or a damaged one, is refused", "[restart]") {
  const auto dir = fresh_dir("badrestart");
  const std::string file = write_file(dir / "case.yaml", kCase);
  REQUIRE(run_ckpd("run " + file + " --quiet --set time.steps=40 --out " + (dir / "a").string())
              .exit_code == 0);
  const auto checkpoint = (dir / "a" / "checkpoint.h5").string();

  CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "b").string() +
                             " --set materials.steel.youngs_modulus=100e9 --restart " + checkpoint);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("another case") != std::string::npos);

  write_file(dir / "garbage.h5", "this is not a checkpoint");
  r = run_ckpd("run " + file + " --quiet --out " + (dir / "c").string() + " --restart " +
               (dir / "garbage.h5").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("not an HDF5 file") != std::string::npos);

  // The first half of a real checkpoint: HDF5's signature but missing data.
  {
    std::ifstream in(checkpoint, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "truncated.h5", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  r = run_ckpd("run " + file + " --quiet --out " + (dir / "d").string() + " --restart " +
               (dir / "truncated.h5").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("checkpoint") != std::string::npos);

  r = run_ckpd("run " + file + " --quiet --out " + (dir / "e").string() + " --restart " +
               (dir / "missing.h5").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("checkpoint not found") != std::string::npos);
}
