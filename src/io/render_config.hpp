#pragma once
// The [render] table: rendered PNG frames of evaluation episodes (docs/rendering.md).
//
//   [render]
//   enabled = true            # render at the end of a co-design run
//   episodes = 1              # the first N evaluation episodes of d* and of the runner-up
//   every_steps = 1           # a frame every N simulation steps (1: every 0.01 s step; 5: one
//                             # per decision), plus the settled state before the first step
//   width = 1280              # pixels
//   height = 720
//   azimuth_deg = -20.0       # camera: 0 looks along +y (the whisker's bending plane face on)
//   elevation_deg = 15.0
//   fov_deg = 30.0            # vertical field of view
//   zoom = 1.0                # > 1 moves the camera closer than the automatic framing
//   strain_range = "episode"  # "episode": colour scale over all frames shown; "fixed": below
//   strain_min_percent = -1.0
//   strain_max_percent = 5.0
//   arrow_mm_per_mN = 1.0     # length of the contact-force arrow
//   png_compression = 1       # zlib level 0..9
#include "base/range.hpp"
#include "io/toml_reader.hpp"

namespace codesign::io {

namespace render_config_range {
inline constexpr Range<std::int64_t> episodes{1, 1000};
inline constexpr Range<std::int64_t> every_steps{1, 100000};
inline constexpr Range<std::int64_t> width{64, 4096};
inline constexpr Range<std::int64_t> height{64, 4096};
inline constexpr Range<double> azimuth_deg{-180.0, 180.0};
inline constexpr Range<double> elevation_deg{-89.0, 89.0};
inline constexpr Range<double> fov_deg{5.0, 120.0};
inline constexpr Range<double> zoom{0.1, 10.0};
inline constexpr Range<double> strain_percent{-100.0, 100.0};
inline constexpr Range<double> arrow_mm_per_mN{0.0, 100.0};
inline constexpr Range<std::int64_t> png_compression{0, 9};
}  // namespace render_config_range

struct RenderConfig {
  bool enabled = true;
  int episodes = 1;
  int every_steps = 1;
  int width = 1280;
  int height = 720;
  double azimuth_deg = -20.0;
  double elevation_deg = 15.0;
  double fov_deg = 30.0;
  double zoom = 1.0;
  bool fixed_strain_range = false;    // strain_range = "fixed"
  double strain_min_percent = -1.0;
  double strain_max_percent = 5.0;
  double arrow_mm_per_mN = 1.0;
  int png_compression = 1;

  // Throws InputError naming `where` and the field for a value out of its range or
  // strain_min_percent ≥ strain_max_percent.
  void validate(const std::string& where) const;
};

// Reads [render] of a run config (absent: defaults) and finishes it.
RenderConfig read_render_config(TableReader& root);

}  // namespace codesign::io
