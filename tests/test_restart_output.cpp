// What a restart does to the files of the run it continues: the history keeps only the rows the
// uninterrupted run writes (not the extra row of a run stopped off its schedule, by SIGTERM or an
// earlier end), and the XDMF indexes keep listing the kept frames from the first moment on (a
// restart that is stopped, or whose disk is full, before its next frame leaves them indexed); a
// frame whose content hash does not hold is not kept.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "full_disk.hpp"
#include "run_helpers.hpp"
#include "src/output/field_writer.hpp"

using namespace ckpd::testing;
namespace fs = std::filesystem;

namespace {

// `ckpd run` of the strip of tests/data/pulled_strip.yaml with a history row every 10 steps, a
// frame and a checkpoint every 20 (the steps are set by each test).
const std::string kRun = "run " CKPD_SOURCE_DIR
                         "/tests/data/pulled_strip.yaml --quiet --threads 1 --set "
                         "output.history_interval=10 --set output.field_interval=20 --set "
                         "output.checkpoint_interval=20";

// The time steps an XDMF index lists (one Time element each).
std::size_t frames_listed(const fs::path& xdmf) {
  const std::string text = file_text(xdmf);
  std::size_t n = 0;
  for (auto at = text.find("<Time "); at != std::string::npos; at = text.find("<Time ", at + 1))
    ++n;
  return n;
}

}  // namespace

TEST_CASE("a restart from a run stopped off the row schedule writes the uninterrupted history",
          "[restart][output]") {
  const fs::path dir = fresh_dir("history-rows");
  const std::string out = " --out ";
  REQUIRE(run_ckpd(kRun + " --set time.steps=60" + out + (dir / "whole").string()).exit_code == 0);
  // Stopped at step 23 with a checkpoint there: its last row (step 23) is off the schedule, as
  // the row a run stopped by SIGTERM writes at the signal's step.
  const fs::path part = dir / "part";
  REQUIRE(run_ckpd("run " CKPD_SOURCE_DIR "/tests/data/pulled_strip.yaml --quiet --threads 1 --set "
                   "output.history_interval=10 --set output.field_interval=20 --set "
                   "output.checkpoint_interval=23 --set time.steps=23" +
                   out + part.string())
              .exit_code == 0);
  CHECK(file_text(part / "history.csv").find("\n23,") != std::string::npos);
  fs::copy_file(part / "checkpoint.h5", dir / "at23.h5");
  const CommandResult r = run_ckpd(kRun + " --set time.steps=60" + out + part.string() +
                                   " --restart " + (dir / "at23.h5").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(file_text(part / "history.csv") == file_text(dir / "whole" / "history.csv"));
}

TEST_CASE("SIGTERM then a restart writes the history of the uninterrupted run",
          "[restart][output]") {
  const fs::path dir = fresh_dir("sigterm-rows");
  const fs::path out = dir / "out";
  const CommandResult stopped =
      run_ckpd(kRun + " --set time.steps=100000000 --out " + out.string() +
               " & pid=$!; sleep 2; kill -TERM $pid; wait $pid; echo exit=$?");
  INFO(stopped.output);
  REQUIRE(stopped.output.find("exit=130") != std::string::npos);
  const long long at = read_json(out / "summary.json")["steps"];
  const long long end = (at / 10 + 3) * 10;
  const std::string steps = " --set time.steps=" + std::to_string(end);
  const CommandResult more = run_ckpd(kRun + steps + " --out " + out.string() + " --restart " +
                                      (out / "checkpoint.h5").string());
  INFO(more.output);
  REQUIRE(more.exit_code == 0);
  REQUIRE(run_ckpd(kRun + steps + " --out " + (dir / "whole").string()).exit_code == 0);
  CHECK(file_text(out / "history.csv") == file_text(dir / "whole" / "history.csv"));
}

TEST_CASE("a restart keeps its kept frames indexed from the start", "[restart][output]") {
  const fs::path dir = fs::canonical(fresh_dir("restart-index"));
  const fs::path out = dir / "out";
  // Frames at steps 0, 20, 40 and a checkpoint at 40.
  REQUIRE(run_ckpd(kRun + " --set time.steps=40 --out " + out.string()).exit_code == 0);
  REQUIRE(frames_listed(out / "fields.xdmf") == 3);
  fs::copy_file(out / "checkpoint.h5", dir / "at40.h5");
  const std::string restart = " --out " + out.string() + " --restart " + (dir / "at40.h5").string();
  SECTION("a restart with no step left writes no frame, and the index stays") {
    const CommandResult r = run_ckpd(kRun + " --set time.steps=40" + restart);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(frames_listed(out / "fields.xdmf") == 3);
    CHECK(frames_listed(out / "fields_strip.xdmf") == 3);
  }
  SECTION("a restart whose disk fills up before its next frame leaves the frames indexed") {
    for (long long k = 1; k <= 12; ++k) {
      const CommandResult r =
          run_ckpd_on_full_disk(out, k, kRun + " --set time.steps=60" + restart);
      INFO("full from write " << k << ": " << r.output);
      CHECK(r.exit_code != 0);
      CHECK(frames_listed(out / "fields.xdmf") >= 3);
      CHECK(frames_listed(out / "fields_strip.xdmf") >= 3);
    }
  }
}

TEST_CASE("a frame changed after it was written is refused by its content hash, and not kept",
          "[restart][output]") {
  const fs::path dir = fs::canonical(fresh_dir("frame-hash"));
  const fs::path out = dir / "out";
  REQUIRE(run_ckpd(kRun + " --set time.steps=40 --out " + out.string()).exit_code == 0);
  // One byte of frame 1's displacement flipped where HDF5 keeps it.
  {
    const fs::path frame = out / "fields" / ckpd::FieldWriter::frame_name(1);
    const hid_t file = H5Fopen(frame.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(file >= 0);
    const hid_t set = H5Dopen2(file, "/body_0/displacement", H5P_DEFAULT);
    REQUIRE(set >= 0);
    const haddr_t offset = H5Dget_offset(set);
    H5Dclose(set);
    H5Fclose(file);
    REQUIRE(offset != HADDR_UNDEF);
    std::fstream bytes(frame, std::ios::in | std::ios::out | std::ios::binary);
    bytes.seekg(static_cast<std::streamoff>(offset) + 8);
    const char c = static_cast<char>(bytes.get() ^ 0x10);
    bytes.seekp(static_cast<std::streamoff>(offset) + 8);
    bytes.put(c);
  }
  CHECK_NOTHROW(ckpd::FieldWriter::read_frame(out.string(), 0));
  CHECK_THROWS_WITH(ckpd::FieldWriter::read_frame(out.string(), 1),
                    Catch::Contains("the content hash does not match"));
  // A restart keeps the frames before it and writes on from there.
  fs::copy_file(out / "checkpoint.h5", dir / "at40.h5");
  const CommandResult r = run_ckpd(kRun + " --set time.steps=60 --out " + out.string() +
                                   " --restart " + (dir / "at40.h5").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(frames_listed(out / "fields.xdmf") == 2);  // step 0 and the restart's step 60
  CHECK_NOTHROW(ckpd::FieldWriter::read_frame(out.string(), 1));
  CHECK_FALSE(fs::exists(out / "fields" / ckpd::FieldWriter::frame_name(2)));
}
