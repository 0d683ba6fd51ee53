// The bad-input table: every kind of input a user hands the binary — configs, command-line
// flags, meshes, policy files, checkpoints — broken in many distinct ways. Each case must stop
// with one message that names the file and the key or field and says what is allowed, exit
// with a non-zero status, and leave every file already in the scratch folder (an earlier
// complete run, the inputs themselves) byte for byte as it was.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rl/policy_file.hpp"
#include "run_binary.hpp"
#include "tiny_run.hpp"

namespace {

namespace fs = std::filesystem;
using codesign::test::run_codesign;

// A complete run in a few seconds: 2 designs x 2 decisions per iteration, 4 iterations.
const std::string kTinyRun = [] {
  codesign::test::TinyRun r = codesign::test::TinyRun::minimal();
  r.total_timesteps = 16;
  r.designs_per_update = 2;
  r.exploration_end = 4;
  r.exploitation_start = 8;
  r.eval_episodes = 1;
  r.checkpoint_every = 4;
  r.seed = 3;
  return r.toml();
}();

// Two tetrahedra sharing the face (1, 2, 3), one on each side; base, tip and chamber_1 tagged.
constexpr const char* kMesh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
4
2 1 "base"
2 2 "tip"
2 3 "chamber_1"
3 4 "whisker"
$EndPhysicalNames
$Entities
0 0 3 1
1 0 0 0 1 1 1 1 1 0
2 0 0 0 1 1 1 1 2 0
3 0 0 0 1 1 1 1 3 0
1 0 0 0 1 1 1 1 4 3 1 2 3
$EndEntities
$Nodes
1 5 1 5
3 1 0 5
1
2
3
4
5
0 0 0
1 0 0
0 1 0
0 0 1
0.3 0.3 -1
$EndNodes
$Elements
4 5 1 5
2 1 2 1
1 1 3 4
2 2 2 1
2 2 3 4
2 3 2 1
3 1 2 5
3 1 4 2
4 1 2 3 4
5 1 2 3 5
$EndElements
)";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// Every file under `dir` with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

// The bytes of a binary file (policy, checkpoint) with the trailing FNV-1a checksum made right
// again after an edit: the file is then damaged only where the case says.
std::string with_checksum(std::string b) {
  const std::uint64_t sum = codesign::rl::fnv1a64(
      std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(b.data()), b.size() - 8));
  b.replace(b.size() - 8, 8, reinterpret_cast<const char*>(&sum), 8);
  return b;
}

class BadInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("codesign_badinput_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    write(*dir_ / "tiny.toml", kTinyRun);
    const auto r = run_codesign("--config " + (*dir_ / "tiny.toml").string() + " -o " + (*dir_ / "run").string() +
                                " --quiet --threads 1");
    ASSERT_EQ(r.status, 0) << r.output;
    write(*dir_ / "good.msh", kMesh);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* BadInput::dir_ = nullptr;

struct Case {
  std::string name;
  // Writes the case's input files into the scratch folder and returns the command line.
  std::function<std::string(const fs::path&)> prepare;
  std::vector<std::string> expect;  // every one must appear in the message
};

std::string str(const fs::path& p) { return p.string(); }

// A config case: `text` as <name>.toml given to the main job over the earlier run, even with
// --force (a valid config would start afresh and so change the folder: the test would see it).
Case config(const std::string& name, const std::string& text, std::vector<std::string> expect) {
  return {"config_" + name,
          [name, text](const fs::path& d) {
            write(d / (name + ".toml"), text);
            return "--config " + str(d / (name + ".toml")) + " -o " + str(d / "run") + " --force --quiet";
          },
          std::move(expect)};
}

Case cli(const std::string& name, const std::string& args, std::vector<std::string> expect) {
  return {"cli_" + name, [args](const fs::path& d) {
            std::string a = args;
            for (std::size_t p; (p = a.find("DIR")) != std::string::npos;) a.replace(p, 3, str(d));
            return a;
          },
          std::move(expect)};
}

Case mesh(const std::string& name, std::function<std::string(std::string)> edit, std::vector<std::string> expect) {
  return {"mesh_" + name,
          [name, edit](const fs::path& d) {
            write(d / (name + ".msh"), edit(kMesh));
            return "check " + str(d / (name + ".msh"));
          },
          std::move(expect)};
}

Case policy(const std::string& name, std::function<std::string(std::string)> edit, std::vector<std::string> expect,
            const std::string& config_text = "") {
  return {"policy_" + name,
          [name, edit, config_text](const fs::path& d) {
            write(d / (name + ".bin"), edit(slurp(d / "run" / "policy.bin")));
            std::string args = "check " + str(d / (name + ".bin"));
            if (!config_text.empty()) {
              write(d / (name + ".toml"), config_text);
              args += " --config " + str(d / (name + ".toml"));
            }
            return args;
          },
          std::move(expect)};
}

// A checkpoint case: a copy of the earlier run whose checkpoint (or log) `edit` damages, resumed.
Case checkpoint(const std::string& name, std::function<void(const fs::path&)> edit, std::vector<std::string> expect,
                const std::string& config_text = kTinyRun) {
  return {"checkpoint_" + name,
          [name, edit, config_text](const fs::path& d) {
            const fs::path run = d / ("resume_" + name);
            fs::copy(d / "run", run, fs::copy_options::recursive);
            edit(run);
            write(d / (name + ".toml"), config_text);
            return "--config " + str(d / (name + ".toml")) + " -o " + str(run) + " --resume --quiet";
          },
          std::move(expect)};
}

std::vector<Case> cases() {
  const std::string tiny = kTinyRun;
  auto cut = [](double f) { return [f](std::string b) { return b.substr(0, static_cast<std::size_t>(b.size() * f)); }; };
  auto flip = [](std::size_t at) { return [at](std::string b) { b[at] ^= 0x10; return b; }; };
  auto ckpt_edit = [](std::function<std::string(std::string)> e) {
    return [e](const fs::path& run) { write(run / "checkpoint.bin", e(slurp(run / "checkpoint.bin"))); };
  };
  return {
      // ---- configs (run over the earlier run with --force)
      config("range", "[material]\npoisson_ratio = 0.7\n", {"range.toml: material.poisson_ratio", "allowed [0, 0.49]"}),
      config("type", "[scene]\ninclination_deg = \"thirty\"\n", {"type.toml: scene.inclination_deg", "expected a number in", "got a string"}),
      config("unknown_key", "[scene]\ninclinaton_deg = 30\n", {"unknown_key.toml: scene.inclinaton_deg", "unknown key in [scene]", "allowed keys:", "inclination_deg"}),
      config("unknown_table", "[renderer]\nwidth = 3\n", {"unknown_table.toml: renderer", "unknown key at the top level", "allowed keys:"}),
      config("syntax", "[task]\nepisode_steps = = 3\n", {"syntax.toml:2:", "invalid TOML"}),
      config("duplicate_key", "[task]\nkappa = 1\nkappa = 2\n", {"duplicate_key.toml:3:", "invalid TOML"}),
      config("table_as_value", "task = 3\n", {"table_as_value.toml: task", "expected a table, got an integer"}),
      config("hold_divides", "[task]\nepisode_steps = 250\naction_hold_steps = 7\n", {"hold_divides.toml: task.action_hold_steps", "must divide task.episode_steps (250)"}),
      config("strain_order", "[task]\nstrain_min = 0.1\nstrain_max = 0.05\n", {"strain_order.toml: task.strain_max", "must exceed task.strain_min"}),
      config("observation", "[task]\nobservation = \"camera\"\n", {"observation.toml: task.observation", "\"camera\" is not allowed", "\"paper\", \"proprioceptive\", \"no_feedback\""}),
      config("phase_order", "[codesign]\nexploration_end = 900000\n", {"phase_order.toml: codesign.exploration_end", "allowed [0, 799999]"}),
      config("designs_zero", "[codesign]\ndesigns_per_update = 0\n", {"designs_zero.toml: codesign.designs_per_update", "allowed [1, 1024]"}),
      config("seed_negative", "[codesign]\nseed = -1\n", {"seed_negative.toml: codesign.seed", "out of range; allowed [0, "}),
      config("integer_as_float", "[codesign]\ntotal_timesteps = 1.5\n", {"integer_as_float.toml: codesign.total_timesteps", "expected an integer in", "got a number"}),
      config("baseline", "[codesign]\nbaseline = \"random\"\n", {"baseline.toml: codesign.baseline", "\"none\", \"single_design\""}),
      config("randomize_range", "[randomize]\nyoungs_modulus = 2.0\n", {"randomize_range.toml: randomize.youngs_modulus", "allowed [0, 0.9]"}),
      config("randomize_key", "[randomize]\nyoung_modulus = 0.2\n", {"randomize_key.toml: randomize.young_modulus", "unknown key in [randomize]", "youngs_modulus"}),
      config("wall_range", "[randomize]\nwall_mm = 0.5\n", {"wall_range.toml: randomize.wall_mm", "allowed [0, 0.25]"}),
      config("stiffness_cue", "[task]\nstiffness_cue = \"camera\"\n", {"stiffness_cue.toml: task.stiffness_cue", "\"none\", \"inflation\", \"true_modulus\""}),
      config("n_steps", "[ppo]\nn_steps = 7\n", {"n_steps.toml: ppo.n_steps", "must equal the decisions per episode", "= 50"}),
      config("hidden_empty_layer", "[ppo]\nactor_hidden = [64, 0]\n", {"hidden_empty_layer.toml: ppo.actor_hidden", "element 1 = 0 is out of range"}),
      config("precision", "[ppo]\nmatmul_precision = \"fp8\"\n", {"precision.toml: ppo.matmul_precision", "\"auto\""}),
      config("learning_rate", "[ppo]\nlearning_rate = -1e-3\n", {"learning_rate.toml: ppo.learning_rate", "out of range; allowed"}),
      config("solver_method", "[solver]\nmethod = \"magic\"\n", {"solver_method.toml: solver.method", "\"fast\"", "\"exact\""}),
      config("dt_zero", "[solver]\ndt_s = 0\n", {"dt_zero.toml: solver.dt_s", "allowed [1e-05, 0.1]"}),
      config("mesh_size", "[mesh]\nmax_size_mm = 100\n", {"mesh_size.toml: mesh.max_size_mm", "allowed [0.2, 50]"}),
      config("geometry", "[geometry]\nbase_diameter_mm = 3\n", {"geometry.toml: [geometry] (length_mm, base_diameter_mm", "cannot hold design 0"}),
      config("pressures_length", "[sim]\npressures_kPa = [1, 2, 3]\n", {"pressures_length.toml: sim.pressures_kPa", "an array of", "got 3 elements"}),
      config("telemetry_type", "[telemetry]\nurl = 5\n", {"telemetry_type.toml: telemetry.url", "expected a string, got an integer"}),
      config("faults_decision", "[faults]\nnan_pressure_every = 3\nat_decision = 50\n", {"faults_decision.toml: faults.at_decision", "allowed [0, 49]"}),
      config("faults_unknown", "[faults]\nnan_every = 3\n", {"faults_unknown.toml: faults.nan_every", "unknown key in [faults]", "nan_pressure_every"}),
      // ---- command line and files given to it
      cli("config_missing", "--config DIR/none.toml -o DIR/run --force", {"DIR/none.toml: cannot open config file"}),
      cli("config_directory", "--config DIR -o DIR/run --force", {": cannot read config file: it is a directory"}),
      cli("threads_range", "run --config DIR/tiny.toml -o DIR/run --threads -1", {"--threads", "-1", "1024"}),
      cli("resume_and_force", "run --config DIR/tiny.toml -o DIR/run --resume --force", {"--resume", "excludes", "--force"}),
      cli("config_required", "run -o DIR/run", {"--config", "required"}),
      cli("stop_after_text", "run --config DIR/tiny.toml -o DIR/run --stop-after soon", {"--stop-after", "soon"}),
      cli("earlier_run", "--config DIR/tiny.toml -o DIR/run", {"DIR/run: already holds", "--resume", "--force"}),
      cli("resume_nothing", "--config DIR/tiny.toml -o DIR/empty_run --resume", {"DIR/empty_run: no checkpoint.bin", "start the run without --resume"}),
      cli("design_range", "mesh --design 110 -o DIR/j.msh", {"--design", "110"}),
      cli("survey_designs_range", "survey --config DIR/tiny.toml -o DIR/survey --designs 3-110", {"--designs: '3-110' is not a design index or range A-B within 0..109"}),
      cli("sweep_designs_reversed", "sweep --config DIR/tiny.toml -o DIR/sweep --designs 9-4", {"--designs: '9-4' is not a design index or range A-B within 0..109"}),
      cli("sweep_threads_range", "sweep --config DIR/tiny.toml -o DIR/sweep --threads 1025", {"--threads", "1025", "1024"}),
      cli("unknown_command", "frobnicate --config DIR/tiny.toml", {"unknown command 'frobnicate'", "allowed: run, survey, mesh, sim, train-gym, figures, check, config-keys, render, baseline, sweep, refine, evaluate, verify, bench"}),
      cli("verify_no_run", "verify --run DIR/none", {"DIR/none/config.toml: not found; verify needs a finished co-design run folder"}),
      cli("verify_phase_set", "verify --run DIR/run --phase-set train", {"--phase-set", "train"}),
      cli("verify_with", "verify --run DIR/run --with DIR/none", {"--with: DIR/none/result.toml: not found; each --with folder must be a finished co-design run"}),
      cli("vtk_every_negative", "sim --config DIR/tiny.toml -o DIR/sim --vtk-every -3", {"--vtk-every", "-3"}),
      cli("check_unknown_file", "check DIR/tiny.toml", {"DIR/tiny.toml: not a file codesign reads", "allowed: a gmsh .msh 4.1 mesh"}),
      // ---- meshes (codesign check)
      mesh("flat_tet", [](std::string m) { return replaced(m, "0.3 0.3 -1", "0.3 0.3 0"); }, {"flat_tet.msh:", "expected a tetrahedron of non-zero volume, got a flat one"}),
      mesh("inverted_tet", [](std::string m) { return replaced(m, "0.3 0.3 -1", "0.2 0.2 0.5"); }, {"inverted_tet.msh:", "expected tetrahedra that do not overlap", "inverted element"}),
      mesh("no_base", [](std::string m) { return replaced(m, "2 1 \"base\"", "2 1 \"clamp\""); }, {"no_base.msh: physical group \"base\": no triangles", "\"tip\" and \"chamber_1\""}),
      mesh("no_chamber", [](std::string m) { return replaced(m, "2 3 \"chamber_1\"", "2 3 \"cavity\""); }, {"no_chamber.msh: physical group \"chamber_1\": no triangles"}),
      mesh("version", [](std::string m) { return replaced(m, "4.1 0 8", "2.2 0 8"); }, {"version.msh:2:", "expected 4.1 in $MeshFormat, got '2.2'"}),
      mesh("binary", [](std::string m) { return replaced(m, "4.1 0 8", "4.1 1 8"); }, {"binary.msh:2:", "file type 0 (ASCII)", "save the mesh as ASCII"}),
      mesh("truncated", [](std::string m) { return m.substr(0, m.find("0 0 1\n")); }, {"truncated.msh:", "got end of file"}),
      mesh("unknown_node", [](std::string m) { return replaced(m, "5 1 2 3 5", "5 1 2 3 9"); }, {"unknown_node.msh:", "expected a node tag listed in $Nodes, got 9"}),
      mesh("duplicate_node", [](std::string m) { return replaced(m, "\n4\n5\n0 0 0", "\n4\n4\n0 0 0"); }, {"duplicate_node.msh: node tag 4 appears twice in $Nodes"}),
      mesh("nan_coordinate", [](std::string m) { return replaced(m, "0 0 1\n", "0 0 nan\n"); }, {"nan_coordinate.msh:", "expected finite node coordinates"}),
      mesh("quadratic_tets", [](std::string m) { return replaced(m, "3 1 4 2", "3 1 11 2"); }, {"quadratic_tets.msh:", "expected element type 4 (linear tetrahedron)", "got type 11"}),
      // ---- policy files (codesign check)
      policy("truncated", cut(0.5), {"policy file", "truncated.bin", "checksum mismatch (file is corrupt or truncated)"}),
      policy("checksum", flip(40), {"policy file", "checksum.bin", "checksum mismatch"}),
      policy("magic", flip(0), {"magic.bin: not a file codesign reads", "allowed: a gmsh .msh 4.1 mesh, a policy file"}),
      policy("version", [](std::string b) { b[8] = 4; return with_checksum(b); }, {"policy file", "version.bin", "unsupported version 4 (this build reads versions 1 to 3)"}),
      policy("trailing_bytes", [](std::string b) { return with_checksum(b.insert(b.size() - 8, "xxxx")); }, {"policy file", "trailing_bytes.bin", "4 unexpected bytes after the last field"}),
      policy("network_sizes", [](std::string b) { return b; }, {"policy file", "network_sizes.bin", "actor hidden sizes [4] differ from", "ppo.actor_hidden = [8]"},
             replaced(tiny, "actor_hidden = [4]", "actor_hidden = [8]")),
      policy("observation", [](std::string b) { return b; }, {"policy file", "observation.bin", "obs_dim 7 differs from", "task.observation = \"paper\" with task.history = 0 needs 6"},
             replaced(tiny, "\"proprioceptive\"", "\"paper\"")),
      // ---- checkpoints (run --resume over a copy of the earlier run)
      checkpoint("truncated", ckpt_edit(cut(0.6)), {"checkpoint", "checkpoint.bin", "checksum mismatch (file damaged or truncated)"}),
      checkpoint("checksum", ckpt_edit(flip(100)), {"checkpoint", "checkpoint.bin", "checksum mismatch"}),
      checkpoint("empty", ckpt_edit([](std::string) { return std::string(); }), {"checkpoint", "checkpoint.bin", "too short (0 bytes)"}),
      checkpoint("magic", ckpt_edit(flip(1)), {"checkpoint", "checkpoint.bin", "bad magic (not a codesign checkpoint)"}),
      checkpoint("version", ckpt_edit([](std::string b) { b[8] = 9; return with_checksum(b); }), {"checkpoint", "checkpoint.bin", "unsupported version 9 (this build reads versions 1 to 3)"}),
      checkpoint("other_config", [](const fs::path&) {}, {"checkpoint", "checkpoint.bin", "written by a run with another config", "config.toml"},
                 replaced(kTinyRun, "seed = 3", "seed = 4")),
      checkpoint("network_sizes",
                 ckpt_edit([](std::string b) {
                   // actor vector at byte 44: u64 length, then floats; one parameter less
                   std::uint64_t n = 0;
                   b.copy(reinterpret_cast<char*>(&n), 8, 44);
                   --n;
                   b.replace(44, 8, reinterpret_cast<const char*>(&n), 8);
                   b.erase(52, 4);
                   return with_checksum(b);
                 }),
                 {"checkpoint", "checkpoint.bin", "network sizes differ from this config's"}),
      checkpoint("trailing_bytes", ckpt_edit([](std::string b) { return with_checksum(b.insert(b.size() - 8, "abc")); }),
                 {"checkpoint", "checkpoint.bin", "3 unexpected bytes after the last field"}),
      checkpoint("log_too_short", [](const fs::path& run) { write(run / "sampled.csv", "k,t"); },
                 {"sampled.csv: log file has 3 bytes, the checkpoint expects at least", "does not belong to this checkpoint"}),
      checkpoint("log_header", [](const fs::path& run) { write(run / "ppo.csv", replaced(slurp(run / "ppo.csv"), "pg_loss", "pgloss!")); },
                 {"ppo.csv: log file header differs from this version's columns"}),
      checkpoint("log_missing", [](const fs::path& run) { fs::remove(run / "q_disc.csv"); },
                 {"q_disc.csv: log file to resume is missing"}),
      {"checkpoint_check_without_config", [](const fs::path& d) { return "check " + str(d / "run" / "checkpoint.bin"); },
       {"checkpoint", "checkpoint.bin", "--config is required to check a checkpoint"}},
  };
}

TEST_F(BadInput, EveryCaseIsOneClearMessageNonZeroExitAndChangesNoFile) {
  const std::vector<Case> all = cases();
  std::set<std::string> names;
  for (const Case& c : all) names.insert(c.name);
  EXPECT_EQ(names.size(), all.size()) << "case names must be distinct";
  EXPECT_GE(all.size(), 40u);
  const fs::path& d = *dir_;
  for (const Case& c : all) {
    SCOPED_TRACE(c.name);
    const std::string args = c.prepare(d);
    const auto before = snapshot(d);
    const auto r = run_codesign(args);
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.status, -1) << "did not exit normally: " << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    // One message: a single line (CLI11 adds a "Run with --help" hint line to its own errors).
    const std::string first = r.output.substr(0, r.output.find('\n'));
    const bool cli11 = r.output.find("Run with --help") != std::string::npos;
    if (!cli11) {
      EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    }
    for (std::string e : c.expect) {
      for (std::size_t p; (p = e.find("DIR")) != std::string::npos;) e.replace(p, 3, d.string());
      EXPECT_NE(first.find(e), std::string::npos) << "expected \"" << e << "\" in: " << r.output;
    }
    const auto after = snapshot(d);
    EXPECT_EQ(after.size(), before.size()) << "files appeared or vanished";
    for (const auto& [file, bytes] : before) {
      const auto it = after.find(file);
      ASSERT_NE(it, after.end()) << file << " vanished";
      EXPECT_TRUE(it->second == bytes) << file << " changed";
    }
  }
}

}  // namespace
