#pragma once
// Makes a run folder ready for a co-design run, before any simulator is built (docs/run_folder.md).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "run/checkpoint.hpp"
#include "run/run_settings.hpp"

namespace codesign::run {

// With `resume`: the checkpoint to continue from (checked against the config's fingerprint), or
// none when the run stopped before its first checkpoint and DIR/config.toml is this config (it
// then starts again). Otherwise DIR is refused if it holds an earlier run (unless `force`), and
// created. A run that starts (again) has results of an earlier run removed and its config files
// written: config.toml (`resolved`) and, when not resuming, config.input.toml (the file as given).
std::optional<Checkpoint> prepare_run_folder(const RunSettings& settings, const std::filesystem::path& dir,
                                             bool resume, bool force, const std::string& resolved,
                                             std::uint64_t fingerprint);

}  // namespace codesign::run
