// Before any work, a command checks its output paths: an output that resolves to one of its
// inputs, to an existing data file inside an input folder (a bag's .db3, a data set's images
// and lists; not a result such as a .tum left there before), or to another of
// its outputs (through links, "..", hard links) is refused, and so is
// one that cannot be written (missing or read-only folder, a folder where a file is expected).
// A run that would end by failing to write, or by overwriting its own recording, never starts.
//
//   checkOutputs({{"--input", a.input}, {"--map", a.map}}, {{"--out", a.out}, {"--plot", a.plot}});
#pragma once

#include <string>
#include <vector>

namespace polyloc::cli {

struct PathArg {
  std::string option;  // "--out"
  std::string path;    // empty: not given, skipped
};

// Throws std::runtime_error naming the options. Missing parent folders of `files` are created;
// `folders` are output folders (created if missing), that must not be an input.
void checkOutputs(const std::vector<PathArg>& inputs, const std::vector<PathArg>& files,
                  const std::vector<PathArg>& folders = {});

}  // namespace polyloc::cli
