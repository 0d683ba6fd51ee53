#pragma once
// The lock of a run folder, as every command that writes into one takes it (io/formats/run_lock.hpp
// holds the lock file itself).
#include <memory>
#include <string>

#include "io/formats/run_lock.hpp"

namespace codesign::run {

// Takes DIR/.lock (creating DIR), or, with only_if_exists, returns null when DIR is not a folder
// (a --resume, or a command that writes into a finished run folder: its own checks then say what
// is missing). Throws InputError if another process holds the lock; says so on stderr when it
// takes over the lock of a process that was killed.
std::unique_ptr<io::RunLock> lock_run_folder(const std::string& dir, bool only_if_exists);

// `codesign render --run DIR -o OUT`: the lock of DIR when OUT lies inside DIR (frames written
// into the run folder), else null: it only reads DIR.
std::unique_ptr<io::RunLock> lock_run_folder_for_output(const std::string& dir, const std::string& out);

}  // namespace codesign::run
