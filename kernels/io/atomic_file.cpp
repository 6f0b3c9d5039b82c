#include <polyloc/io/atomic_file.hpp>
#include <polyloc/io/error.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <filesystem>
#include <unistd.h>

namespace polyloc {
namespace {
namespace fs = std::filesystem;

std::string tmpName(const std::string& path) {
  const fs::path p(path);
  const fs::path name = "." + p.stem().string() + ".partial-" + std::to_string(::getpid()) + p.extension().string();
  return (p.parent_path() / name).string();
}

// Creates `tmp` (exclusively, so a stale one from a dead run is replaced first); names `path` in errors.
void create(const std::string& path, const std::string& tmp) {
  if (path.empty()) throw IoError("output path is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a folder, expected a file to write");
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty() && !fs::is_directory(dir, ec))
    throw IoError(path + ": cannot write: folder " + dir.string() + " does not exist");
  ::unlink(tmp.c_str());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw IoError(path + ": cannot write in its folder: " + std::strerror(errno));
  ::close(fd);
}
}  // namespace

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(tmpName(path_)), unwinding_(std::uncaught_exceptions()) {
  create(path_, tmp_);
}

AtomicFile::~AtomicFile() {
  if (done_) return;
  if (std::uncaught_exceptions() > unwinding_) {
    discard();
    return;
  }
  try {
    commit();
  } catch (const std::exception& e) {  // a destructor must not throw: say it, keep the temporary
    std::fprintf(stderr, "polyloc: %s\n", e.what());
  }
}

void AtomicFile::commit() {
  if (done_) return;
  done_ = true;
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw IoError(path_ + ": cannot move the finished " + tmp_ + " into place: " + std::strerror(errno));
}

void AtomicFile::discard() {
  if (done_) return;
  done_ = true;
  ::unlink(tmp_.c_str());
}

void checkWritable(const std::string& path) {
  const std::string probe = tmpName(path);
  create(path, probe);
  ::unlink(probe.c_str());
}

}  // namespace polyloc
