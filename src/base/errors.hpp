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

// A file the program could not write or create (disk full, no permission, a read-only file
// system): the message names the file and the system's reason (strerror), and says what was
// left as it was. `codesign` prints it like an InputError and exits with status 2: the run did
// not fail, its surroundings did.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace codesign
