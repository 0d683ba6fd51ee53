// libFuzzer harness: the TOML config readers with every table: a run config as every command
// reads it (run::read_run_config: [geometry], [mesh], [fibres], [material], [scene], [solver],
// [sim], [task], [codesign], [ppo], [telemetry], unknown keys and tables), and the same text as
// a train-gym config ([env], [ppo], [train]).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "base/errors.hpp"
#include "io/config/gym_config.hpp"
#include "io/config/toml_reader.hpp"
#include "run/run_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace codesign;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    io::TableReader root = io::TableReader::from_string(text, "fuzz.toml");
    (void)run::read_run_config(root);
  } catch (const InputError&) {
  }
  try {
    io::TableReader root = io::TableReader::from_string(text, "fuzz.toml");
    (void)io::read_gym_config(root);
  } catch (const InputError&) {
  }
  return 0;
}
