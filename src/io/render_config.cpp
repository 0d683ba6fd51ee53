#include "io/render_config.hpp"

#include <string>

#include "base/errors.hpp"

namespace codesign::io {

namespace {

template <class T, class V>
void check(const std::string& where, const char* key, V value, Range<T> r) {
  if (!r.contains(static_cast<T>(value)))
    throw InputError(where + ": render." + key + ": value " + std::to_string(value) + " is out of range; allowed [" +
                     std::to_string(r.lo) + ", " + std::to_string(r.hi) + "]");
}

}  // namespace

void RenderConfig::validate(const std::string& where) const {
  namespace R = render_config_range;
  check(where, "episodes", episodes, R::episodes);
  check(where, "every_steps", every_steps, R::every_steps);
  check(where, "width", width, R::width);
  check(where, "height", height, R::height);
  check(where, "azimuth_deg", azimuth_deg, R::azimuth_deg);
  check(where, "elevation_deg", elevation_deg, R::elevation_deg);
  check(where, "fov_deg", fov_deg, R::fov_deg);
  check(where, "zoom", zoom, R::zoom);
  check(where, "strain_min_percent", strain_min_percent, R::strain_percent);
  check(where, "strain_max_percent", strain_max_percent, R::strain_percent);
  check(where, "arrow_mm_per_mN", arrow_mm_per_mN, R::arrow_mm_per_mN);
  check(where, "png_compression", png_compression, R::png_compression);
  if (!(strain_min_percent < strain_max_percent))
    throw InputError(where + ": render.strain_min_percent (" + std::to_string(strain_min_percent) +
                     ") must be below render.strain_max_percent (" + std::to_string(strain_max_percent) + ")");
}

RenderConfig read_render_config(TableReader& root) {
  namespace R = render_config_range;
  TableReader t = root.table("render");
  RenderConfig c;
  c.enabled = t.boolean("enabled", c.enabled);
  c.episodes = static_cast<int>(t.integer("episodes", c.episodes, R::episodes));
  c.every_steps = static_cast<int>(t.integer("every_steps", c.every_steps, R::every_steps));
  c.width = static_cast<int>(t.integer("width", c.width, R::width));
  c.height = static_cast<int>(t.integer("height", c.height, R::height));
  c.azimuth_deg = t.number("azimuth_deg", c.azimuth_deg, R::azimuth_deg);
  c.elevation_deg = t.number("elevation_deg", c.elevation_deg, R::elevation_deg);
  c.fov_deg = t.number("fov_deg", c.fov_deg, R::fov_deg);
  c.zoom = t.number("zoom", c.zoom, R::zoom);
  c.fixed_strain_range = t.string("strain_range", "episode", {"episode", "fixed"}) == "fixed";
  c.strain_min_percent = t.number("strain_min_percent", c.strain_min_percent, R::strain_percent);
  c.strain_max_percent = t.number("strain_max_percent", c.strain_max_percent, R::strain_percent);
  c.arrow_mm_per_mN = t.number("arrow_mm_per_mN", c.arrow_mm_per_mN, R::arrow_mm_per_mN);
  c.png_compression = static_cast<int>(t.integer("png_compression", c.png_compression, R::png_compression));
  if (!(c.strain_min_percent < c.strain_max_percent))
    t.fail("strain_min_percent", "must be below strain_max_percent (" + std::to_string(c.strain_max_percent) + ")");
  t.finish();
  return c;
}

}  // namespace codesign::io
