#include "run/prepare_folder.hpp"

#include <fstream>
#include <sstream>
#include <system_error>

#include "base/errors.hpp"
#include "io/formats/atomic_file.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

namespace fs = std::filesystem;

std::optional<Checkpoint> prepare_run_folder(const RunSettings& settings, const fs::path& dir, bool resume,
                                             bool force, const std::string& resolved, std::uint64_t fingerprint) {
  const fs::path ckpt_path = dir / run_file::kCheckpoint;
  std::optional<Checkpoint> ckpt;
  std::error_code ec;
  bool fresh = !resume;
  if (resume) {
    if (fs::exists(ckpt_path, ec)) {
      ckpt = load_checkpoint(ckpt_path.string(), fingerprint);
    } else {
      // Stopped before its first checkpoint: nothing to keep, so start this run's config again.
      std::ifstream in(dir / run_file::kConfig, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      if (!in || text.str() != resolved)
        throw InputError(dir.string() + ": no checkpoint.bin (and no config.toml of this config) to resume from; "
                         "start the run without --resume");
      fresh = true;
    }
  }
  if (fresh && !resume) {
    for (const char* f : {run_file::kConfig, run_file::kCheckpoint, run_file::kResult, run_file::kEpisodes})
      if (fs::exists(dir / f, ec) && !force)
        throw InputError(dir.string() + ": already holds " + f + " of an earlier run; continue it with --resume, "
                         "or choose another -o, or pass --force to start afresh");
    fs::create_directories(dir, ec);
    if (ec) throw InputError(dir.string() + ": cannot create the run folder: " + ec.message());
  }
  if (fresh) {
    for (const char* f : {run_file::kCheckpoint, run_file::kResult, run_file::kPolicy}) fs::remove(dir / f, ec);
    for (const KeptCheckpoint& kc : kept_checkpoints(settings.loop.codesign)) fs::remove(dir / kc.file, ec);
    io::write_file_atomically((dir / run_file::kConfig).string(), [&](std::ostream& out) { out << resolved; });
    if (!resume)
      io::write_file_atomically((dir / run_file::kConfigInput).string(),
                                [&](std::ostream& out) { out << settings.config_text; });
  }
  return ckpt;
}

}  // namespace codesign::run
