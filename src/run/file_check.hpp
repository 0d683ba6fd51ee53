#pragma once
// `codesign check FILE [--config run.toml]` (docs/reliability.md): reads a file a user brings
// from elsewhere — a gmsh .msh 4.1 mesh, a policy file, a checkpoint — with the readers the
// program uses, and prints one line saying what it holds. With a config it also applies the
// rules of file_fit.hpp (a policy's network and observation sizes; a checkpoint's config
// fingerprint and network sizes; a checkpoint needs the config). A mesh must carry the surfaces
// a whisker needs. Writes nothing.
#include <string>

namespace codesign::run {

// Recognises the file by its first bytes (or a .msh name) and checks it; `config` may be empty.
// Any defect is an InputError naming the file and the field.
void check_file(const std::string& file, const std::string& config);

}  // namespace codesign::run
