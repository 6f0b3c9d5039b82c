// Outputs that never leave half a file where a good one was: the writer writes the temporary
// `FOLDER/.NAME.partial-PID.EXT` (same folder, so the rename is atomic; same extension, so
// writers that pick a format by extension still work), and commit() renames it onto NAME.
//
//   AtomicFile f(out);                        // throws IoError now if FOLDER cannot take a file
//   std::ofstream s(f.tmp()); ... ; s.close();
//   f.commit();                               // or leave the scope normally: committed too
//
// Leaving the scope by an exception removes the temporary and leaves NAME as it was.
#pragma once

#include <string>

namespace polyloc {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  const std::string& path() const { return path_; }
  const std::string& tmp() const { return tmp_; }
  void commit();  // throws IoError naming both paths
  void discard();

 private:
  std::string path_, tmp_;
  int unwinding_ = 0;  // std::uncaught_exceptions() at construction
  bool done_ = false;
};

// Throws IoError (naming the path and why) when `path` cannot become a file: its folder is
// missing or not writable, or it is a folder. Creates and removes a probe file.
void checkWritable(const std::string& path);

}  // namespace polyloc
