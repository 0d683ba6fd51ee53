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
#include <string>

#include "base/enum_names.hpp"
#include "base/range.hpp"
#include "io/config/toml_reader.hpp"

namespace codesign::io {

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

enum class StrainRange { Episode, Fixed };
inline constexpr EnumNames<StrainRange, 2> kStrainRangeNames{{{StrainRange::Episode, "episode"},
                                                              {StrainRange::Fixed, "fixed"}}};

template <class V>
void describe_render_table(V& v, RenderConfig& c) {
  constexpr Range<double> kStrainPercent{-100.0, 100.0};
  v.boolean({"enabled", "", "render frames at the end of a co-design run"}, c.enabled);
  v.integer({"episodes", "", "the first N evaluation episodes of d* and of the runner-up"}, c.episodes, {1, 1000});
  v.integer({"every_steps", "", "a frame every N simulation steps, plus the settled state"}, c.every_steps,
            {1, 100000});
  v.integer({"width", "px", "frame width"}, c.width, {64, 4096});
  v.integer({"height", "px", "frame height"}, c.height, {64, 4096});
  v.number({"azimuth_deg", "deg", "camera azimuth; 0 looks along +y (the bending plane face on)"}, c.azimuth_deg,
           {-180.0, 180.0});
  v.number({"elevation_deg", "deg", "camera elevation"}, c.elevation_deg, {-89.0, 89.0});
  v.number({"fov_deg", "deg", "vertical field of view"}, c.fov_deg, {5.0, 120.0});
  v.number({"zoom", "", "> 1 moves the camera closer than the automatic framing"}, c.zoom, {0.1, 10.0});
  StrainRange range = c.fixed_strain_range ? StrainRange::Fixed : StrainRange::Episode;
  v.choice({"strain_range", "", "colour scale over the frames shown (\"episode\") or the fixed one below"}, range,
           kStrainRangeNames);
  c.fixed_strain_range = range == StrainRange::Fixed;
  v.number({"strain_min_percent", "%", "fixed colour scale: lowest strain"}, c.strain_min_percent, kStrainPercent);
  v.number({"strain_max_percent", "%", "fixed colour scale: highest strain"}, c.strain_max_percent, kStrainPercent);
  v.number({"arrow_mm_per_mN", "mm/mN", "length of the contact-force arrow"}, c.arrow_mm_per_mN, {0.0, 100.0});
  v.integer({"png_compression", "", "zlib level of the PNG files"}, c.png_compression, {0, 9});
  v.require(c.strain_min_percent < c.strain_max_percent, "strain_min_percent", [&] {
    return "must be below strain_max_percent (" + std::to_string(c.strain_max_percent) + ")";
  });
}

// Reads [render] of a run config (absent: defaults) and finishes it.
RenderConfig read_render_config(TableReader& root);

}  // namespace codesign::io
