#include "run/run_settings.hpp"

#include <utility>

namespace codesign::run {

RunSettings run_settings(const RunConfig& c, std::string config_text) {
  RunSettings s;
  s.spec = c.spec;
  s.scene = c.scene;
  s.solver = c.solver;
  s.loop = {c.task, c.codesign, c.ppo};
  s.config_text = std::move(config_text);
  return s;
}

}  // namespace codesign::run
