#pragma once
// Writes a whole file so that readers see either the old file or the complete new one, never a
// half-written one: the content goes to PATH.tmp, which is renamed over PATH only after it was
// written and closed without error. On any failure the temporary file is removed, PATH is left
// as it was, and the error is thrown: codesign::FileError naming PATH.tmp and strerror(errno)
// for I/O failures (base/file_write.hpp), or whatever `write` threw.
#include <functional>
#include <ostream>
#include <string>

namespace codesign::io {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary = false);

}  // namespace codesign::io
