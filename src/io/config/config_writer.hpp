#pragma once
// Writing config tables back as TOML: the inverse of the readers of fem_config.hpp,
// mesh_config.hpp and gym_config.hpp (read_ppo_config), with the same key names and units.
//
//   [material] [scene] [solver] [geometry] [mesh] [fibres]   write_fem_tables
//   [ppo]                                                     write_ppo_table
//
// Every key a reader reads is written, with the value the struct holds, so reading the text
// back with those readers gives the same structs bit for bit: numbers are written in the
// shortest form that reads back as the same double, and a value the reader scales (kPa -> Pa,
// N -> µN, degrees -> radians) is written as the number that the reader's own expression maps
// back onto the stored value exactly (TomlTableWriter::scaled, ::degrees). Two cases cannot be
// expressed in a file and are written as documented at write_ppo_table.
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "fem/simulator.hpp"
#include "io/config/toml_writer.hpp"
#include "fem/whisker_model.hpp"
#include "rl/ppo.hpp"

namespace codesign::io {

// [material], [scene] (with tip_region_mm of spec.model; plate_phase_deg in degrees), [solver]
// (method "fast" / "exact"), [geometry] (not its design: the design index is chosen per run),
// [mesh], [fibres] (layout, axial_stiffness_N, tension_only).
void write_fem_tables(std::ostream& out, const fem::WhiskerModelSpec& spec, const fem::SceneConfig& scene,
                      const fem::SolverConfig& solver);

// [ppo]: every key read_ppo_config reads. matmul_precision is written as the resolved
// "float32" / "bf16" (never "auto"), so a file with "bf16" reads back only where AVX-512 BF16
// is available. target_kl and ent_decay_start / ent_decay_end are written only when set: an
// unset one reads back unset only over defaults that leave it unset (read_ppo_config's default
// {}); over rl::paper_ppo_config() the paper's value fills it (the file cannot say "none").
void write_ppo_table(std::ostream& out, const rl::PpoConfig& ppo);

}  // namespace codesign::io
