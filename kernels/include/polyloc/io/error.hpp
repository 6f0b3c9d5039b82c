// The one error type of kernels/io: what could not be read or written, naming the file.
#pragma once

#include <stdexcept>

namespace polyloc {

class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace polyloc
