#include "io/config/render_config.hpp"

#include <string>

#include "base/config_check.hpp"
#include "base/errors.hpp"
#include "io/config/table_keys.hpp"

namespace codesign::io {

void RenderConfig::validate(const std::string& where) const {
  RenderConfig c = *this;  // the description takes the fields by reference
  if (const auto p = config::first_problem([&](auto& v) { describe_render_table(v, c); }))
    throw InputError(where + ": render." + *p);
}

RenderConfig read_render_config(TableReader& root) {
  RenderConfig c;
  read_keys(root, "render", [&](auto& v) { describe_render_table(v, c); });
  return c;
}

}  // namespace codesign::io
