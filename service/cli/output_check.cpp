#include "cli/output_check.hpp"

#include <polyloc/io/atomic_file.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <iterator>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace polyloc::cli {
namespace output_check_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)
namespace fs = std::filesystem;

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);  // links, hard links
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec), cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
  return ca == cb;
}

// An existing file of the kind a recording folder holds (a bag's .db3 and metadata.yaml, a data
// set's images, lists and poses, an MCAP) inside an input folder: one of its inputs. A result a
// run left there before (.tum, .ply, .json) may be written again.
bool insideFolder(const std::string& file, const std::string& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec) || !fs::exists(file, ec)) return false;
  std::string ext = fs::path(file).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  static const char* kData[] = {".png", ".jpg", ".jpeg", ".txt", ".db3", ".yaml", ".mcap", ".log", ".gz"};
  if (std::none_of(std::begin(kData), std::end(kData), [&](const char* e) { return ext == e; })) return false;
  const fs::path f = fs::weakly_canonical(fs::absolute(file, ec), ec), d = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  const auto [end, _] = std::mismatch(d.begin(), d.end(), f.begin(), f.end());
  return end == d.end();
}
}  // namespace output_check_impl

void checkOutputs(const std::vector<PathArg>& inputs, const std::vector<PathArg>& files,
                  const std::vector<PathArg>& folders) {
  using namespace output_check_impl;
  std::vector<const PathArg*> outs;
  for (const auto& f : files)
    if (!f.path.empty()) outs.push_back(&f);
  for (const auto& f : folders)
    if (!f.path.empty()) outs.push_back(&f);
  for (size_t i = 0; i < outs.size(); ++i) {
    for (const auto& in : inputs)
      if (!in.path.empty() && samePath(outs[i]->path, in.path))
        throw std::runtime_error(fmt::format("{} {} is the input {}: refusing to overwrite it", outs[i]->option,
                                             outs[i]->path, in.option));
      else if (!in.path.empty() && insideFolder(outs[i]->path, in.path))
        throw std::runtime_error(fmt::format("{} {} is a file of the input folder {} {}: refusing to overwrite it",
                                             outs[i]->option, outs[i]->path, in.option, in.path));
    for (size_t j = 0; j < i; ++j)
      if (samePath(outs[i]->path, outs[j]->path))
        throw std::runtime_error(fmt::format("{} and {} are the same file {}: each output needs its own",
                                             outs[j]->option, outs[i]->option, outs[i]->path));
  }
  try {
    for (const auto& f : files) {
      if (f.path.empty()) continue;
      // Missing parent folders are made, as the commands always did; one that cannot be is the error.
      std::error_code ec;
      if (const fs::path dir = fs::path(f.path).parent_path(); !dir.empty() && !fs::exists(dir, ec)) {
        fs::create_directories(dir, ec);
        if (ec) throw std::runtime_error(f.path + ": cannot create its folder: " + ec.message());
      }
      checkWritable(f.path);
    }
    for (const auto& f : folders) {
      if (f.path.empty()) continue;
      std::error_code ec;
      if (fs::exists(f.path, ec) && !fs::is_directory(f.path, ec))
        throw std::runtime_error(f.path + ": is a file, expected a folder");
      fs::create_directories(f.path, ec);
      if (ec) throw std::runtime_error(f.path + ": cannot create the folder: " + ec.message());
      checkWritable((fs::path(f.path) / "probe").string());
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("output: {}", e.what()));
  }
}

}  // namespace polyloc::cli
