// A disk that fills up at every write of a small run, one failure point after the other
// (tests/fault/full_disk.c, preloaded into `ckpd run`): the run never exits 0 and never crashes,
// says what failed once, leaves no file that passes for complete (no summary, no temporary, no
// cut-off history row, every indexed frame whole with its hash), and its last checkpoint continues
// to the very state, history and frames of the run the disk never stopped.
#include <hdf5.h>
#include <libxml/parser.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "full_disk.hpp"
#include "run_helpers.hpp"
#include "src/output/field_writer.hpp"
#include "src/output/hdf5_io.hpp"

using namespace ckpd::testing;
namespace fs = std::filesystem;

namespace {

// A 2D strip of 153 points, 12 steps: a history row every 2 steps, a frame and a checkpoint
// every 4.
const std::string kStrip = CKPD_SOURCE_DIR "/tests/data/pulled_strip.yaml";

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The checkpoint's content hash: it covers every value a restart restores.
std::string checkpoint_hash(const fs::path& path) {
  ckpd::hdf5::silence_errors();
  ckpd::hdf5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                          "open " + path.string());
  return ckpd::hdf5::read_string_attribute(file, "content_hash");
}

// The frames an XDMF index lists (it must parse as XML), each read back with its hash checked.
std::size_t indexed_frames(const fs::path& out, const std::string& index) {
  const fs::path path = out / index;
  const xmlDocPtr doc = xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET);
  INFO(index);
  REQUIRE(doc != nullptr);
  xmlFreeDoc(doc);
  const std::string text = file_text(path);
  std::size_t frames = 0;
  while (text.find(ckpd::FieldWriter::frame_name(frames) + ":") != std::string::npos) {
    CHECK_NOTHROW(ckpd::FieldWriter::read_frame(out.string(), frames));
    ++frames;
  }
  return frames;
}

// Every line of a history ends with its newline and has the header's number of columns.
void require_whole_history(const fs::path& path) {
  const std::string text = file_text(path);
  REQUIRE(!text.empty());
  CHECK(text.back() == '\n');
  std::istringstream lines(text);
  std::string header, line;
  std::getline(lines, header);
  const auto columns = occurrences(header, ",");
  while (std::getline(lines, line)) CHECK(occurrences(line, ",") == columns);
}

}  // namespace

TEST_CASE("a disk full at any write never ends a run as complete, and its checkpoint continues it",
          "[output][disk_full]") {
  const fs::path dir = fs::canonical(fresh_dir("disk-full"));
  const std::string run = "run " + kStrip + " --quiet --threads 1 --out ";
  // The run the disk never stops, counting its writes: the failure points.
  const fs::path whole = dir / "whole";
  const CommandResult counted = run_ckpd_on_full_disk(whole, 0, run + whole.string(), dir / "n");
  INFO(counted.output);
  REQUIRE(counted.exit_code == 0);
  const long long writes = std::stoll(file_text(dir / "n"));
  REQUIRE(writes > 20);
  const std::string whole_history = file_text(whole / "history.csv");
  const std::string whole_checkpoint = checkpoint_hash(whole / "checkpoint.h5");
  const std::size_t whole_frames = indexed_frames(whole, "fields.xdmf");
  REQUIRE(whole_frames == 4);
  int restarted = 0;
  for (long long k = 1; k <= writes; ++k) {
    const fs::path out = dir / "out";
    fs::remove_all(out);
    const CommandResult r = run_ckpd_on_full_disk(out, k, run + out.string());
    INFO("the disk full from write " << k << " of " << writes << ":\n" << r.output);
    // Exit 1 (a write failed) or 2 (found at set-up); never 0, never a signal.
    REQUIRE((r.exit_code == 1 || r.exit_code == 2));
    CHECK(occurrences(r.output, "ckpd: error") == 1);
    CHECK(r.output.find("No space left on device") != std::string::npos);
    CHECK_FALSE(fs::exists(out / "summary.json"));
    for (const auto& e : fs::recursive_directory_iterator(out))
      CHECK(e.path().extension() != ".partial");
    if (r.exit_code == 2) {  // the run could not start: nothing of it is left
      CHECK_FALSE(fs::exists(out / "run.log"));
      CHECK_FALSE(fs::exists(out / "history.csv"));
      CHECK_FALSE(fs::exists(out / "fields.xdmf"));
      continue;
    }
    require_whole_history(out / "history.csv");
    std::size_t listed = 0;
    if (fs::exists(out / "fields.xdmf")) {
      listed = indexed_frames(out, "fields.xdmf");
      // A frame is renamed into place, then indexed: at most one complete frame is not listed.
      std::size_t files = 0;
      for (const auto& e : fs::directory_iterator(out / "fields"))
        files += e.path().extension() == ".h5";
      CHECK(files >= listed);
      CHECK(files <= listed + 1);
    }
    if (fs::exists(out / "fields_strip.xdmf")) {
      const std::size_t series = indexed_frames(out, "fields_strip.xdmf");
      CHECK(series >= listed);  // the body's series is written just before fields.xdmf
      CHECK(series <= listed + 1);
    }
    if (!fs::exists(out / "checkpoint.h5")) continue;
    // The last complete checkpoint continues to the run the disk never stopped, bit for bit.
    fs::copy_file(out / "checkpoint.h5", dir / "last.h5", fs::copy_options::overwrite_existing);
    const CommandResult c =
        run_ckpd(run + out.string() + " --restart " + (dir / "last.h5").string());
    INFO(c.output);
    REQUIRE(c.exit_code == 0);
    CHECK(checkpoint_hash(out / "checkpoint.h5") == whole_checkpoint);
    CHECK(file_text(out / "history.csv") == whole_history);
    CHECK(indexed_frames(out, "fields.xdmf") == whole_frames);
    CHECK(indexed_frames(out, "fields_strip.xdmf") == whole_frames);
    ++restarted;
  }
  CHECK(restarted > 0);
}

TEST_CASE("a disk full under ranks that write their files together ends every rank with a message",
          "[output][disk_full][mpi]") {
  if (run_ckpd("--version").output.find("MPI none") != std::string::npos ||
      std::system("command -v mpirun >/dev/null 2>&1") != 0) {
    WARN("ckpd is built without MPI, or there is no mpirun: not run");
    return;
  }
  const fs::path dir = fs::canonical(fresh_dir("disk-full-mpi"));
  const fs::path out = dir / "out";
  // Two ranks on distributed memory, each writing its points into the shared frames and
  // checkpoints (or, without parallel HDF5, rank 0 alone). A write that fails inside parallel
  // HDF5 on one rank only is ended by the watchdog, here after 10 s.
  const std::string mpirun =
      "timeout 120 mpirun --oversubscribe --allow-run-as-root -np 2 -x OMP_NUM_THREADS=1 -x "
      "CKPD_SHARED_WRITE_TIMEOUT=10 -x "
      "LD_PRELOAD=" CKPD_FULL_DISK " -x CKPD_FULL_DISK_DIR=" +
      out.string();
  const std::string run = std::string(CKPD_BINARY) +
                          " run " CKPD_SOURCE_DIR "/tests/mpi/two_bodies.yaml --quiet --out " +
                          out.string() +
                          " --set time.steps=20 --set output.field_interval=10"
                          " --set output.checkpoint_interval=10";
  const auto shell = [](const std::string& command) {
    CommandResult r;
    FILE* pipe = popen((command + " 2>&1; echo exit=$?").c_str(), "r");
    char buf[4096];
    while (pipe && std::fgets(buf, sizeof buf, pipe)) r.output += buf;
    if (pipe) pclose(pipe);
    const auto at = r.output.rfind("exit=");
    if (at != std::string::npos) r.exit_code = std::stoi(r.output.substr(at + 5));
    return r;
  };
  const CommandResult whole =
      shell(mpirun + " -x CKPD_FULL_DISK_COUNT=" + (dir / "n").string() + " " + run);
  INFO(whole.output);
  REQUIRE(whole.exit_code == 0);
  // Each rank counts its own writes (the count file holds the last rank's to end).
  const long long writes = std::stoll(file_text(dir / "n"));
  REQUIRE(writes > 4);
  // Every sixth of the writes, and the last few (the final checkpoint's flush and close).
  std::vector<long long> points;
  for (long long k = 1; k <= writes; k += std::max(1LL, writes / 6)) points.push_back(k);
  for (long long k = std::max(1LL, writes - 10); k <= writes; k += 3) points.push_back(k);
  for (long long k : points) {
    fs::remove_all(out);
    const CommandResult r =
        shell(mpirun + " -x CKPD_FULL_DISK_CALL=" + std::to_string(k) + " " + run);
    INFO("the disk full from write " << k << " of " << writes << " of each rank:\n" << r.output);
    CHECK(r.exit_code != 0);
    CHECK(r.exit_code != 124);  // not ended by the timeout: no rank waits for ever
    CHECK(r.output.find("ckpd: error") != std::string::npos);
    CHECK_FALSE(fs::exists(out / "summary.json"));
  }
}
