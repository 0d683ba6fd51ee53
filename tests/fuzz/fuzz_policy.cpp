// libFuzzer harness: the policy file reader (rl::parse_policy = rl::load_policy without the
// file), then one deterministic action of a policy it accepted.
#include <cstddef>
#include <cstdint>

#include "base/errors.hpp"
#include "fuzz_common.hpp"
#include "rl/policy_file.hpp"

namespace {

void parse(std::span<const unsigned char> bytes) {
  try {
    const codesign::rl::Policy p(codesign::rl::parse_policy(bytes, "fuzz.policy"));
    (void)p.act_deterministic(Eigen::VectorXd::Zero(p.obs_dim()));
  } catch (const codesign::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  parse(std::span<const unsigned char>(data, size));
  parse(codesign::fuzz::with_valid_checksum(data, size));
  return 0;
}
