// Outputs never destroy inputs, a reused RESULTS_DIR keeps no stale file, failed writes and
// non-finite flags are errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "io/atomic_dir.hpp"
#include "io/io_error.hpp"
#include "io/output_guard.hpp"
#include "mapping/ply_io.hpp"
#include "tests/hostile/hostile_util.hpp"

namespace vigs::hostile {
namespace {

namespace fs = std::filesystem;

TEST(OutputGuard, RefusesTheSameInodeThroughLinksAndDots) {
  TempDir dir;
  const std::string in = dir.file("in.txt");
  write_text(in, "input");
  fs::create_symlink(in, dir.file("link.txt"));
  fs::create_hard_link(in, dir.file("hard.txt"));
  for (const std::string& out :
       {in, dir.file("./in.txt"), dir.file("link.txt"), dir.file("hard.txt")}) {
    EXPECT_THROW(io::refuse_output_over_inputs(out, {dir.file("other"), in}), io::IoError) << out;
  }
  EXPECT_NO_THROW(io::refuse_output_over_inputs(dir.file("new.txt"), {in}));
  write_text(dir.file("other.txt"), "x");
  EXPECT_NO_THROW(io::refuse_output_over_inputs(dir.file("other.txt"), {in}));
}

TEST(OutputGuard, RefusesAnOutputFolderHoldingAnInput) {
  TempDir dir;
  fs::create_directories(dir.file("res/sub"));
  write_text(dir.file("res/sub/seq.mcap"), "x");
  EXPECT_THROW(io::refuse_output_dir_over_inputs(dir.file("res"), {dir.file("res/sub/seq.mcap")}),
               io::IoError);
  fs::create_directory_symlink(dir.file("res"), dir.file("alias"));
  EXPECT_THROW(io::refuse_output_dir_over_inputs(dir.file("res"), {dir.file("alias/sub/seq.mcap")}),
               io::IoError);
  EXPECT_NO_THROW(
      io::refuse_output_dir_over_inputs(dir.file("res/sub2"), {dir.file("res/sub/seq.mcap")}));
}

/// Every command with an output path refuses one that is its input, and leaves it unchanged.
TEST(OutputGuard, EveryCommandRefusesToOverwriteItsInput) {
  TempDir dir;
  write_recording(dir.file("rec.mcap"), 3, [](int, CraftedFrame&) {});
  mapping::GaussianMap map;
  map.resize(1);
  map.quat_wxyz[0] = 1.0f;
  mapping::write_gaussian_ply(dir.file("map.ply"), map);
  write_text(dir.file("cam.yaml"), "robot: hostile\n");
  write_text(dir.file("frames.txt"), "0 c.png d.png 0 0 0 0 0 0 1\n");
  const std::string rec = read_text(dir.file("rec.mcap")), ply = read_text(dir.file("map.ply")),
                    cam = read_text(dir.file("cam.yaml")),
                    frames = read_text(dir.file("frames.txt"));
  struct Case {
    std::string args, input;
  };
  const std::string d = dir.path().string() + "/";
  const Case cases[] = {
      {"mcap oni " + d + "rec.mcap " + d + "rec.mcap", "rec.mcap"},
      {"mcap oni " + d + "rec.mcap " + d + "./rec.mcap", "rec.mcap"},
      {"render --map " + d + "map.ply --camera " + d + "cam.yaml --pose '0 0 0 0 0 0 1' --out " +
           d + "map.ply",
       "map.ply"},
      {"render --map " + d + "map.ply --camera " + d + "cam.yaml --pose '0 0 0 0 0 0 1' --out " +
           d + "x.png --depth-out " + d + "cam.yaml",
       "cam.yaml"},
      {"map --camera " + d + "cam.yaml --frames " + d + "frames.txt --out " + d + "frames.txt",
       "frames.txt"},
      {"simulate --config " + d + "cam.yaml --seconds 1 --out " + d + "cam.yaml", "cam.yaml"},
      {"replay " + d + "rec.mcap --out " + d, "rec.mcap"},
  };
  for (const Case& c : cases) {
    const VigsRun r = vigs(dir, c.args);
    EXPECT_EQ(r.status, 1) << c.args << "\n" << r.err;
    EXPECT_TRUE(r.err.find("refusing") != std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_EQ(read_text(dir.file("rec.mcap")), rec);
  EXPECT_EQ(read_text(dir.file("map.ply")), ply);
  EXPECT_EQ(read_text(dir.file("cam.yaml")), cam);
  EXPECT_EQ(read_text(dir.file("frames.txt")), frames);
}

TEST(ResultsDir, ReplacedWholeSoAReusedFolderKeepsNoStaleFile) {
  TempDir dir;
  const std::string out = dir.file("results");
  fs::create_directories(out + "/plots");
  for (const char* name : {"trajectory.tum", "map.ply", "report.md", "plots/ate.png"})
    write_text(out + "/" + name, "stale");
  io::replace_dir_atomically(out, "trajectory.tum", [](const fs::path& tmp) {
    write_text((tmp / "trajectory.tum").string(), "new");
  });
  EXPECT_EQ(read_text(out + "/trajectory.tum"), "new");
  for (const char* name : {"map.ply", "report.md", "plots"})
    EXPECT_FALSE(fs::exists(out + "/" + name)) << name;
  // Nothing left beside it.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(ResultsDir, AFailedWriteLeavesTheOldFolderWhole) {
  TempDir dir;
  const std::string out = dir.file("results");
  fs::create_directories(out);
  write_text(out + "/trajectory.tum", "old");
  write_text(out + "/map.ply", "old map");
  EXPECT_THROW(io::replace_dir_atomically(out, "trajectory.tum",
                                          [](const fs::path& tmp) {
                                            write_text((tmp / "trajectory.tum").string(), "half");
                                            throw std::runtime_error("killed half way");
                                          }),
               std::runtime_error);
  EXPECT_EQ(read_text(out + "/trajectory.tum"), "old");
  EXPECT_EQ(read_text(out + "/map.ply"), "old map");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(ResultsDir, AnUnrelatedFolderIsNeverReplaced) {
  TempDir dir;
  const std::string out = dir.file("home");
  fs::create_directories(out);
  write_text(out + "/thesis.tex", "precious");
  EXPECT_THROW(io::replace_dir_atomically(out, "trajectory.tum", [](const fs::path&) {}),
               io::IoError);
  EXPECT_EQ(read_text(out + "/thesis.tex"), "precious");
}

TEST(FailedWrites, StdoutToDevFullExitsOne) {
  TempDir dir;
  for (const char* args : {"config print", "eval ate --help"}) {
    const int status =
        run_shell(std::string(VIGS_BIN) + " " + args + " > /dev/full 2> " + dir.file("err"));
    EXPECT_EQ(status, 1) << args;  // the help text lost is an error too
    EXPECT_NE(read_text(dir.file("err")).find("cannot write standard output"), std::string::npos)
        << args;
  }
}

TEST(FiniteFlags, NanAndInfNumbersAreUsageErrors) {
  TempDir dir;
  for (const std::string& args : {"simulate --seconds nan --out " + dir.file("a.mcap"),
                                  "simulate --seconds inf --out " + dir.file("a.mcap"),
                                  std::string("eval ate --gt x --est y --max-dt nan"),
                                  std::string("imu play x.csv --delay nan")}) {
    const VigsRun r = vigs(dir, args);
    EXPECT_EQ(r.status, 1) << args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir.file("a.mcap")));
    EXPECT_FALSE(fs::exists(dir.file("a.mcap.partial")));
  }
}

}  // namespace
}  // namespace vigs::hostile
