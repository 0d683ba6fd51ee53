#include "run/config_reference.hpp"

#include <sstream>

#include "core/config_tables.hpp"
#include "fem/config_tables.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/gym_config.hpp"
#include "io/config/render_config.hpp"
#include "run/run_config.hpp"

namespace codesign::run {

std::vector<TableReference> config_tables() {
  using core::CodesignConfig, core::TaskConfig;
  std::vector<TableReference> t;
  const auto add = [&](std::string name, std::string about, std::string read_by, bool resolved, auto describe) {
    t.push_back({std::move(name), std::move(about), std::move(read_by), resolved, io::key_rows(describe), {}, {}, {}});
  };
  const std::string sims = "every command that simulates";
  add("material", "the elastomer: stiffness, mass, damping", sims, true,
      [](auto& v) { fem::Material m; fem::describe_material_table(v, m); });
  add("scene", "the plate and the base's placement", sims, true, [](auto& v) {
    fem::SceneConfig s;
    fem::ModelOptions m;
    fem::describe_scene_table(v, s, m);
  });
  add("solver", "time step and the fast step's solver", sims, true,
      [](auto& v) { fem::SolverConfig s; fem::describe_solver_table(v, s); });
  add("geometry", "the whisker's cone (every design of the space must fit it)", sims, true,
      [](auto& v) { fem::WhiskerGeometry g; fem::describe_geometry_table(v, g); });
  add("mesh", "gmsh's element sizes and the quality limits", sims, true,
      [](auto& v) { fem::MeshOptions o; fem::describe_mesh_table(v, o); });
  add("fibres", "the helical fibre springs: layout and stiffness", sims, true, [](auto& v) {
    fem::FibreLayoutOptions f;
    fem::ModelOptions m;
    fem::describe_fibres_table(v, f, m);
  });
  add("sim", "the open-loop scenario", "`sim`, `render --sim`", false,
      [](auto& v) { fem::SimScenario s; fem::describe_sim_table(v, s); });
  add("task", "the episode, the reward, the observation", "`run` and every command that runs a controller", true,
      [](auto& v) { TaskConfig c; core::describe_task_table(v, c); });
  add("faults", "injected numerical failures (tests); in config.toml only when a fault is on",
      "`run`", true, [](auto& v) {
        TaskConfig c;
        core::describe_faults_table(v, c.faults, c.episode_steps / c.action_hold_steps);
      });
  add("randomize", "physical uncertainty drawn per training episode (off by default); in config.toml only when on",
      "`run`", true, [](auto& v) {
        TaskConfig c;
        core::describe_randomize_table(v, c.randomize);
      });
  add("codesign", "the outer loop: Algorithms 1 and 2, evaluation, checkpoints, seed, baselines", "`run`, `evaluate`",
      true, [](auto& v) {
        CodesignConfig c;
        core::describe_codesign_table(v, c, TaskConfig{}.pressure_max_kPa);
      });
  {
    TableReference ppo{"ppo", "the learner (PPO)", "`run` (over the paper's Table I), `train-gym` (over SB3's)", true,
                       io::key_rows([](auto& v) {
                         rl::PpoConfig c = rl::paper_ppo_config();
                         rl::describe_ppo_table(v, c);
                       }),
                       io::key_rows([](auto& v) {
                         rl::PpoConfig c;
                         rl::describe_ppo_table(v, c);
                       }),
                       "run", "train-gym"};
    t.push_back(std::move(ppo));
  }
  add("pid", "tuning of the PID baselines", "`baseline`, `sweep`", false,
      [](auto& v) { core::PidTuningConfig c; core::describe_pid_table(v, c); });
  add("sweep", "the design landscape", "`sweep`", false, [](auto& v) {
    core::SweepConfig c;
    core::describe_sweep_table(v, c, TaskConfig{}.pressure_max_kPa);
  });
  add("telemetry", "live LCM telemetry", "`run`", false, [](auto& v) {
    RunConfig r;
    describe_telemetry_table(v, r.telemetry_url, r.telemetry_train_every);
  });
  add("render", "PNG frames at the end of a run, and of `render`", "`run`, `render`", false,
      [](auto& v) { io::RenderConfig c; io::describe_render_table(v, c); });
  add("env", "the gym task", "`train-gym`", false, [](auto& v) {
    io::GymTrainConfig g;
    io::describe_env_table(v, g);
  });
  add("train", "the gym run's length, evaluation and output", "`train-gym`", false, [](auto& v) {
    io::GymTrainConfig g;
    io::describe_train_table(v, g);
  });
  return t;
}

namespace {

std::string written_note(const io::KeyRow& r) {
  std::string note;
  if (!r.applies_with.empty()) note += "; only with " + r.applies_with;
  switch (r.written) {
    case config::Written::UnlessDefault: note += "; in config.toml only when not the default"; break;
    case config::Written::WhenSet: note += "; in config.toml only when set"; break;
    case config::Written::Never: note += "; not in config.toml"; break;
    case config::Written::Always: break;
  }
  return note;
}

}  // namespace

std::string config_reference_markdown() {
  std::ostringstream out;
  out << "# Config keys\n\n"
         "Every key of every table, printed by `codesign config-keys` from the one description of each\n"
         "table in the code (`describe_*_table` in `src/fem/config_tables.hpp`, `src/rl/ppo.hpp`,\n"
         "`src/core/config_tables.hpp`, `src/io/config/` and `src/run/run_config.hpp`); a test checks that this\n"
         "page is what the code prints. How files are read, layered and checked: "
         "[configuring.md](configuring.md).\n\n"
         "Every key is optional and takes its default when absent. Ranges are inclusive. A co-design run\n"
         "writes the tables marked *resolved* to its `config.toml`, every key with the value used.\n";
  for (const TableReference& t : config_tables()) {
    out << "\n## [" << t.name << "]\n\n" << t.about << ". Read by " << t.read_by << "."
        << (t.resolved ? " Resolved." : "") << "\n\n";
    const bool two = !t.other_rows.empty();
    out << "| key | type | default" << (two ? " (" + t.label + " / " + t.other_label + ")" : "")
        << " | allowed | unit | meaning |\n|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
      const io::KeyRow& r = t.rows[i];
      std::string def = "`" + r.default_value + "`";
      if (two && i < t.other_rows.size() && t.other_rows[i].default_value != r.default_value)
        def += " / `" + t.other_rows[i].default_value + "`";
      out << "| `" << r.name << "` | " << r.type << " | " << def << " | " << r.allowed << " | " << r.unit
          << " | " << r.meaning << written_note(r) << " |\n";
    }
  }
  return out.str();
}

}  // namespace codesign::run
