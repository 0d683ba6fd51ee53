// libFuzzer harness: the checkpoint reader (run::parse_checkpoint = load_checkpoint without
// the file), then the checks a resumed run applies to what it read before using it: the design
// distribution's state against the paper's 110 designs, the three RNG states, Adam's moments.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "base/errors.hpp"
#include "core/outer_loop.hpp"
#include "fuzz_common.hpp"
#include "rl/adam.hpp"
#include "rl/rng.hpp"
#include "run/checkpoint.hpp"

namespace {

using namespace codesign;

void parse(std::span<const unsigned char> bytes) {
  // The fingerprint the run expects is the one in the file (bytes 12..19), so inputs are not
  // all stopped by the fingerprint test; a mismatch is covered by the unit tests.
  std::uint64_t fp = 0;
  if (bytes.size() >= 20) std::memcpy(&fp, bytes.data() + 12, 8);
  try {
    const run::Checkpoint c = run::parse_checkpoint(bytes, "fuzz.ckpt", fp);
    const core::LoopState& s = c.loop;
    const core::DistributionConfig dc = core::distribution_config(core::CodesignConfig{}, core::TaskConfig{});
    try {
      const core::DesignDistribution d(dc, core::design_chambers(), s.distribution);
      (void)d.entropy(s.t);
    } catch (const std::invalid_argument&) {  // what OuterLoop::restore turns into InputError
    }
    rl::Rng r;
    (void)r.restore(s.rng_act);
    (void)r.restore(s.rng_update);
    (void)r.restore(s.rng_design);
    rl::Adam opt = rl::make_adam(rl::PpoConfig{});
    try {
      opt.restore(s.adam_steps, s.adam_m, s.adam_v);
    } catch (const std::invalid_argument&) {
    }
  } catch (const InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  parse(std::span<const unsigned char>(data, size));
  parse(codesign::fuzz::with_valid_checksum(data, size));
  return 0;
}
