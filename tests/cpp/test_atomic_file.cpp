// Outputs never destroy what was there: a writer that fails midway leaves the old file whole,
// and an output that cannot be written is an error when the writer is made, not at the end.
#include <polyloc/io/atomic_file.hpp>
#include <polyloc/io/error.hpp>
#include <polyloc/io/tum.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_atomic_file {

using namespace polyloc;
using polyloc::test::TempDir;

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
size_t filesIn(const std::filesystem::path& dir) {
  return size_t(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

TEST(AtomicFile, ReplacesOnlyWhenWhole) {
  TempDir tmp;
  const std::string path = (tmp.path() / "out.txt").string();
  std::ofstream(path) << "old";
  {
    AtomicFile f(path);
    std::ofstream(f.tmp()) << "new";
    EXPECT_EQ(slurp(path), "old");  // not yet
  }
  EXPECT_EQ(slurp(path), "new");
  EXPECT_EQ(filesIn(tmp.path()), 1u);  // no temporary left
  try {
    AtomicFile f(path);
    std::ofstream(f.tmp()) << "half";
    throw std::runtime_error("crash midway");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(slurp(path), "new");
  EXPECT_EQ(filesIn(tmp.path()), 1u);
}

TEST(AtomicFile, UnwritableOutputsFailAtOnceNamingThePath) {
  TempDir tmp;
  const auto expectError = [](const std::string& path, const std::string& part) {
    try {
      checkWritable(path);
      ADD_FAILURE() << path << " accepted";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError((tmp.path() / "missing" / "x.tum").string(), "does not exist");
  expectError(tmp.path().string(), "is a folder");
  expectError("/proc/x.tum", "/proc/x.tum");
  EXPECT_NO_THROW(checkWritable((tmp.path() / "x.tum").string()));
  EXPECT_EQ(filesIn(tmp.path()), 0u);  // the probe is gone
  EXPECT_THROW(TumWriter((tmp.path() / "missing" / "x.tum").string()), IoError);
}

TEST(AtomicFile, TumWriterKeepsTheOldTrajectoryUntilClosed) {
  TempDir tmp;
  const std::string path = (tmp.path() / "est.tum").string();
  std::ofstream(path) << "# old\n";
  TumWriter w(path);
  w.write({1'000'000'000, Pose::planar(1, 2, 0)});
  EXPECT_EQ(slurp(path), "# old\n");
  w.close();
  EXPECT_NE(slurp(path).find("1.000000000 1.000000000 2.000000000"), std::string::npos) << slurp(path);
}

}  // namespace polyloc::t_atomic_file
