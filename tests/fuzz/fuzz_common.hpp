#pragma once
// Shared by the libFuzzer harnesses of tests/fuzz/ (see docs/reliability.md).
//
// Every harness defines LLVMFuzzerTestOneInput. With -DCODESIGN_FUZZ=ON (clang) it links
// libFuzzer's main; in the ordinary builds it links replay_main.cpp, which feeds it each file of
// its corpus once (ctest: fuzz_replay_<reader>). A reader may reject an input only with
// codesign::InputError; any other exception, a crash or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "rl/policy_file.hpp"

namespace codesign::fuzz {

// The input with its last 8 bytes replaced by the FNV-1a 64 checksum of the bytes before them,
// as both binary formats (policy files, checkpoints) end. Lets the fuzzer reach the fields
// behind the checksum test; the unchanged input still exercises the test itself.
inline std::vector<unsigned char> with_valid_checksum(const std::uint8_t* data, std::size_t size) {
  std::vector<unsigned char> b(data, data + size);
  if (b.size() < 8) return b;
  const std::uint64_t sum = rl::fnv1a64(std::span<const unsigned char>(b.data(), b.size() - 8));
  std::memcpy(b.data() + b.size() - 8, &sum, 8);
  return b;
}

}  // namespace codesign::fuzz
