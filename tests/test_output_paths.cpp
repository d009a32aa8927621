// The output folder checked before the first step: a folder where a file of the run must go
// (summary.json, a frame, a temporary) is refused with exit 2 before anything is run or written,
// and a disk that is full from the first write leaves no run.log or history.csv behind.
#include <catch2/catch.hpp>
#include <filesystem>

#include "full_disk.hpp"
#include "run_helpers.hpp"

using namespace ckpd::testing;
namespace fs = std::filesystem;

namespace {

// `ckpd run` of the strip of tests/data/pulled_strip.yaml over 2000 steps (long enough that a run
// that starts is seen to start), a frame every 500.
const std::string kRun = "run " CKPD_SOURCE_DIR
                         "/tests/data/pulled_strip.yaml --quiet --set time.steps=2000 --set "
                         "output.field_interval=500 --set output.checkpoint_interval=1000";

// Runs the case into `out` after making a non-empty folder at `in_the_way` (relative to out):
// exit 2 naming it, and nothing of the run written.
void require_refused_before_the_first_step(const std::string& in_the_way) {
  const fs::path dir = fresh_dir("blocked");
  const fs::path out = dir / "out";
  fs::create_directories(out / in_the_way / "inside");
  const CommandResult r = run_ckpd(kRun + " --out " + out.string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find((out / in_the_way).string() + ": a folder is where ckpd writes a file") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(out / "run.log"));
  CHECK_FALSE(fs::exists(out / "history.csv"));
  CHECK_FALSE(fs::exists(out / "fields.xdmf"));
  CHECK_FALSE(fs::exists(out / "fields" / "frame_000000.h5"));
}

}  // namespace

TEST_CASE("a folder in the way of summary.json is refused before the first step", "[output]") {
  require_refused_before_the_first_step("summary.json");
}

TEST_CASE("a folder in the way of a later frame is refused before the first step", "[output]") {
  require_refused_before_the_first_step("fields/frame_000002.h5");
}

TEST_CASE("a folder in the way of a temporary file is refused before the first step", "[output]") {
  require_refused_before_the_first_step("checkpoint.h5.partial");
  require_refused_before_the_first_step("fields/frame_000001.h5.partial");
  require_refused_before_the_first_step("fields_strip.xdmf");
}

TEST_CASE("a disk full from the first writes leaves no run.log or history.csv",
          "[output][disk_full]") {
  const fs::path dir = fs::canonical(fresh_dir("full-at-start"));
  const fs::path out = dir / "out";
  for (long long k = 1; k <= 3; ++k) {
    fs::remove_all(out);
    const CommandResult r = run_ckpd_on_full_disk(out, k, kRun + " --out " + out.string());
    INFO("full from write " << k << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("No space left on device") != std::string::npos);
    CHECK_FALSE(fs::exists(out / "run.log"));
    CHECK_FALSE(fs::exists(out / "history.csv"));
    CHECK_FALSE(fs::exists(out / "summary.json"));
  }
}
