// TUM trajectory files: one pose per line, "timestamp x y z qx qy qz qw" (seconds, metres),
// '#' comments. The format of the TUM RGB-D benchmark and of evo.
#pragma once

#include <polyloc/io/atomic_file.hpp>
#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/error.hpp>

#include <fstream>
#include <string>
#include <vector>

namespace polyloc {

struct StampedPose {
  int64_t stamp_ns = 0;
  Pose pose;
};

class TumReader {  // streams; bad lines are skipped and counted with file:line in warnings
 public:
  explicit TumReader(const std::string& path);  // throws IoError if it cannot be opened
  bool next(StampedPose& out);
  uint64_t rejected() const { return rejected_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  std::string path_;
  std::ifstream in_;
  uint64_t line_ = 0, rejected_ = 0;
  std::vector<std::string> warnings_;
};

std::vector<StampedPose> readTum(const std::string& path);  // whole file, for small inputs

// Writes a temporary beside `path` and renames it into place when closed, or when destroyed
// other than by an exception (io/atomic_file.hpp): the old file stays until the new one is whole.
class TumWriter {
 public:
  explicit TumWriter(const std::string& path);  // throws IoError (now, not at the end of a run)
  ~TumWriter();
  void write(const StampedPose& p);  // throws IoError naming the file when writing fails
  void close();                      // throws IoError

 private:
  std::string path_;
  AtomicFile file_;
  std::ofstream out_;
};

}  // namespace polyloc
