// Each config key is described once and that one description reaches everything: the reference
// page, the writer and the reader. tests/data/every_key.toml and every_key_gym.toml set every key
// of every table to a value other than its default.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/config_tables.hpp"
#include "io/config/config_writer.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/gym_config.hpp"
#include "io/config/render_config.hpp"
#include "io/config/table_keys.hpp"
#include "run/codesign_tables_writer.hpp"
#include "run/config_reference.hpp"
#include "run/run_settings.hpp"
#include "run/run_config.hpp"
#include "test_files.hpp"

namespace codesign::run {
namespace {

const std::string kSource = CODESIGN_SOURCE_DIR;

// "[name]" sections of a TOML text: table → its "key = value" lines as (key, value), in order.
std::map<std::string, std::vector<std::pair<std::string, std::string>>> entries_by_table(const std::string& toml) {
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> out;
  std::istringstream in(toml);
  std::string line, table;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] == '[') {
      table = line.substr(1, line.find(']') - 1);
      out[table];
      continue;
    }
    const std::size_t eq = line.find(" = ");
    if (eq != std::string::npos) out[table].emplace_back(line.substr(0, eq), line.substr(eq + 3));
  }
  return out;
}

// Every table a run config may hold, written from the values read (the resolved config, then
// the tables a run reads but does not resolve).
std::string write_run_tables(const RunConfig& c) {
  const RunSettings s = run_settings(c);
  std::ostringstream out;
  out << resolved_run_config(s.spec, s.scene, s.solver, s.loop);
  fem::SimScenario sim = c.scenario;
  io::write_keys(out, "sim", [&](auto& v) { fem::describe_sim_table(v, sim); });
  core::PidTuningConfig pid = c.pid;
  io::write_keys(out, "pid", [&](auto& v) { core::describe_pid_table(v, pid); });
  core::SweepConfig sweep = c.sweep;
  io::write_keys(out, "sweep", [&](auto& v) { core::describe_sweep_table(v, sweep, c.task.pressure_max_kPa); });
  std::string url = c.telemetry_url;
  int every = c.telemetry_train_every;
  io::write_keys(out, "telemetry", [&](auto& v) { describe_telemetry_table(v, url, every); });
  io::RenderConfig render = c.render;
  io::write_keys(out, "render", [&](auto& v) { io::describe_render_table(v, render); });
  return out.str();
}

std::string write_gym_tables(const io::GymTrainConfig& config) {
  io::GymTrainConfig g = config;
  std::ostringstream out;
  io::write_keys(out, "env", [&](auto& v) { io::describe_env_table(v, g); });
  io::write_ppo_table(out, g.trainer.ppo);
  io::write_keys(out, "train", [&](auto& v) { io::describe_train_table(v, g); });
  return out.str();
}

TEST(ConfigKeys, TheReferencePageIsWhatTheCodePrints) {
  const std::string page = test_files::slurp(kSource + "/docs/config_keys.md");
  EXPECT_EQ(page, config_reference_markdown()) << "regenerate: codesign config-keys > docs/config_keys.md";
}

TEST(ConfigKeys, EveryKeyAppearsOnceOnThePage) {
  const std::string page = config_reference_markdown();
  for (const TableReference& t : config_tables()) {
    const std::size_t start = page.find("\n## [" + t.name + "]\n");
    ASSERT_NE(start, std::string::npos) << t.name;
    const std::size_t end = page.find("\n## [", start + 1);
    const std::string section = page.substr(start, end == std::string::npos ? std::string::npos : end - start);
    std::set<std::string> seen;
    for (const io::KeyRow& r : t.rows) {
      EXPECT_TRUE(seen.insert(r.name).second) << t.name << "." << r.name << " described twice";
      std::size_t n = 0;
      for (std::size_t p = section.find("| `" + r.name + "` |"); p != std::string::npos;
           p = section.find("| `" + r.name + "` |", p + 1))
        ++n;
      EXPECT_EQ(n, 1u) << t.name << "." << r.name;
    }
  }
}

// The run tables and the gym tables of the page, each key once in the writer's output of a
// config that sets them all, with a value other than the default; read back, the same text.
TEST(ConfigKeys, EveryKeyIsWrittenOnceReadBackAndNotADefault) {
  const RunConfig every = read_run_config(kSource + "/tests/data/every_key.toml");
  const std::string run_text = write_run_tables(every);
  const std::string default_run_text = write_run_tables(read_run_config(""));
  io::TableReader gym_root = io::TableReader::from_file(kSource + "/tests/data/every_key_gym.toml");
  const std::string gym_text = write_gym_tables(io::read_gym_config(gym_root));
  io::TableReader gym_default = io::TableReader::from_string("", "(defaults)");
  const std::string default_gym_text = write_gym_tables(io::read_gym_config(gym_default));

  const auto run_entries = entries_by_table(run_text), gym_entries = entries_by_table(gym_text);
  const auto default_run_entries = entries_by_table(default_run_text);
  const auto default_gym_entries = entries_by_table(default_gym_text);
  for (const TableReference& t : config_tables()) {
    const bool gym = t.name == "env" || t.name == "train";
    for (const bool gym_ppo : {false, true}) {
      if (gym_ppo && t.name != "ppo") continue;
      const bool in_gym = gym || gym_ppo;
      const auto& entries = in_gym ? gym_entries : run_entries;
      const auto& defaults = in_gym ? default_gym_entries : default_run_entries;
      ASSERT_TRUE(entries.count(t.name)) << "[" << t.name << "] not written";
      std::vector<std::string> written;
      std::map<std::string, std::string> value, default_value;
      for (const auto& [k, v] : entries.at(t.name)) written.push_back(k), value[k] = v;
      if (defaults.count(t.name))
        for (const auto& [k, v] : defaults.at(t.name)) default_value[k] = v;
      std::size_t exempt_unwritten = 0;
      for (const io::KeyRow& r : t.rows) {
        // Keys that cannot leave their default in these fixtures: [env] name has one allowed value;
        // a gym run's [ppo] privileged_critic must stay false (and so is not written); [sweep]
        // needs one controller on (fixed_theta and pid_strain are off here); matmul_precision
        // "auto" resolves to float32 where the CPU has no AVX-512 BF16.
        const std::string id = (gym_ppo ? "gym." : "") + t.name + "." + r.name;
        const bool exempt = id == "env.name" || id == "gym.ppo.privileged_critic" || id == "sweep.pid_force" ||
                            id == "sweep.pid_estimate" ||
                            (r.name == "matmul_precision" && !rl::bf16_gemm_available());
        const auto n = std::count(written.begin(), written.end(), r.name);
        if (exempt && n == 0) {
          ++exempt_unwritten;
          continue;
        }
        EXPECT_EQ(n, 1) << id;
        // A default absent from the default text is an unset optional or a key written only off
        // its default: any value written now differs from it.
        if (default_value.count(r.name) && !exempt) {
          EXPECT_NE(value.at(r.name), default_value.at(r.name)) << id << " is the default";
        }
      }
      EXPECT_EQ(written.size() + exempt_unwritten, t.rows.size())
          << "[" << t.name << "] has keys the description does not name";
    }
  }
  // Read back (every written key is accepted) and written again: the same text.
  io::TableReader back = io::TableReader::from_string(run_text, "written.toml");
  EXPECT_EQ(write_run_tables(read_run_config(back)), run_text);
  io::TableReader gym_back = io::TableReader::from_string(gym_text, "written.toml");
  EXPECT_EQ(write_gym_tables(io::read_gym_config(gym_back)), gym_text);
}

// The reader accepts exactly the keys described: each table of the fixtures read through its
// description, then every key the reader looked up is a key of the page.
TEST(ConfigKeys, TheReaderAcceptsTheDescribedKeysOnly) {
  std::map<std::string, std::set<std::string>> described;
  for (const TableReference& t : config_tables())
    for (const io::KeyRow& r : t.rows) described[t.name].insert(r.name);
  for (const char* fixture : {"every_key.toml", "every_key_gym.toml"}) {
    const std::string text = test_files::slurp(kSource + "/tests/data/" + fixture);
    for (const auto& [table, entries] : entries_by_table(text)) {
      ASSERT_TRUE(described.count(table)) << fixture << ": [" << table << "]";
      for (const auto& [k, v] : entries) EXPECT_TRUE(described[table].count(k)) << fixture << ": " << table << "." << k;
      // A key the description does not name is refused.
      std::string bad = text;
      bad.insert(bad.find("[" + table + "]\n") + table.size() + 3, "not_a_key = 1\n");
      io::TableReader root = io::TableReader::from_string(bad, "x.toml");
      EXPECT_THROW(fixture == std::string("every_key.toml") ? (void)read_run_config(root) : (void)io::read_gym_config(root),
                   InputError)
          << table;
    }
  }
}

}  // namespace
}  // namespace codesign::run
