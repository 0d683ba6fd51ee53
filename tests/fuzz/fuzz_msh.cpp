// libFuzzer harness: the gmsh MSH 4.1 reader (io::read_msh on the input as a stream).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "base/errors.hpp"
#include "io/formats/msh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    (void)codesign::io::read_msh(in, "fuzz.msh");
  } catch (const codesign::InputError&) {
  }
  return 0;
}
