#include "run/output_dir.hpp"

#include "base/errors.hpp"

namespace codesign::run {

void prepare_output_dir(const std::filesystem::path& dir, const std::string& file, const std::string& what,
                        bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir / file, ec) && !force)
    throw InputError(dir.string() + ": already holds " + file + " of an earlier " + what +
                     "; choose another -o or pass --force");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create output directory: " + ec.message());
}

}  // namespace codesign::run
