#pragma once
// The output folder of a command that writes one result file (sim's trace.csv, survey.csv,
// baseline.toml): refused when it holds that file from an earlier call (unless forced), created
// otherwise; both before any work, so a refused call changes nothing.
#include <filesystem>
#include <string>

namespace codesign::run {

// Throws InputError "DIR: already holds FILE of an earlier WHAT; choose another -o or pass
// --force" when DIR/FILE exists and `force` is off, and "DIR: cannot create output directory:
// ..." when DIR cannot be created.
void prepare_output_dir(const std::filesystem::path& dir, const std::string& file, const std::string& what,
                        bool force);

}  // namespace codesign::run
