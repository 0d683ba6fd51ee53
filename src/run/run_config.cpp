#include "run/run_config.hpp"

#include "io/config/gym_config.hpp"
#include "io/config/mesh_config.hpp"
#include "io/config/table_keys.hpp"
#include "run/codesign_tables_reader.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

RunConfig read_run_config(const std::string& config_path) {
  io::TableReader root = config_path.empty() ? io::TableReader::from_string("", "(defaults)")
                                             : io::TableReader::from_file(config_path);
  return read_run_config(root);
}

RunConfig read_run_config(io::TableReader& root) {
  RunConfig s;
  const io::FemTables fem = io::read_fem_tables(root);
  s.spec = fem.spec;
  s.scene = fem.scene;
  s.solver = fem.solver;
  s.scenario = io::read_sim_scenario(root);
  s.task = read_task_config(root);
  s.codesign = read_codesign_config(root, s.task);
  s.pid = read_pid_config(root);
  s.sweep = read_sweep_config(root, s.task);
  {
    io::TableReader ppo = root.table("ppo");
    s.ppo = io::read_ppo_config(ppo, rl::paper_ppo_config());
    ppo.finish();
  }
  io::read_keys(root, "telemetry", [&](auto& v) { describe_telemetry_table(v, s.telemetry_url, s.telemetry_train_every); });
  s.render = io::read_render_config(root);
  root.finish();
  return s;
}

}  // namespace codesign::run
