#pragma once
// Errors caused by what a user gave us (config, CLI, mesh, checkpoint files).
// The message must already name the file, the key or location, and the allowed range:
// `codesign` prints it once, as is, and exits with status 2.
#include <stdexcept>
#include <string>

namespace codesign {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace codesign
