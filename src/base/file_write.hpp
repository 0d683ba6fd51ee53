#pragma once
// Writing whole files with errors that say why: every failure throws codesign::FileError naming
// the file and strerror(errno) ("No space left on device", "Permission denied", ...).
#include <string>
#include <string_view>

namespace codesign {

// Writes `bytes` to PATH.tmp and renames it over PATH (readers see the old file or the whole
// new one). On failure PATH.tmp is removed and PATH is left as it was.
void write_bytes_atomically(const std::string& path, std::string_view bytes);

// "PATH: WHAT: strerror(error)".
std::string file_error_text(const std::string& path, const std::string& what, int error);

}  // namespace codesign
