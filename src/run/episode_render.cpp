#include "run/episode_render.hpp"

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>

#include "base/errors.hpp"
#include "base/file_write.hpp"
#include "core/open_loop_scenario.hpp"
#include "core/policy_controller.hpp"
#include "fem/design.hpp"
#include "fem/mesh_ops.hpp"
#include "io/formats/atomic_file.hpp"
#include "io/formats/csv_log.hpp"
#include "io/formats/png_file.hpp"
#include "io/render/render_osmesa.hpp"
#include "io/config/toml_reader.hpp"
#include "rl/policy_file.hpp"
#include "run/run_folder.hpp"

namespace codesign::run {

using namespace core;  // this file works on the co-design core's types (src/core)

namespace fs = std::filesystem;

namespace {

std::array<int, 3> sorted(const fem::Tri& t) {
  std::array<int, 3> s{t[0], t[1], t[2]};
  std::sort(s.begin(), s.end());
  return s;
}

io::FrameOverlay overlay_of(const TraceRow& r, const TaskConfig& task, const std::string& title) {
  io::FrameOverlay o;
  o.title = title;
  o.t_s = r.t_s;
  o.theta_rad = r.theta_rad;
  o.force_mN = r.force_mN;
  o.target_mN = task.target_force_mN;
  o.band_fraction = task.tolerance_fraction;
  return o;
}

// Keeps the frames to render: every `every` steps, and always the last step seen.
class FrameKeeper {
 public:
  FrameKeeper(const fem::Model& model, const TaskConfig& task, std::string title, int every, int episode)
      : surface_(model), task_(task), title_(std::move(title)), every_(every), episode_(episode) {}
  void see(const fem::Simulator& sim, const TraceRow& row) {
    RecordedFrame f{episode_, step_, row, surface_.frame(sim), overlay_of(row, task_, title_)};
    if (step_ % every_ == 0) {
      frames_.push_back(std::move(f));
      last_.reset();
    } else {
      last_ = std::move(f);
    }
    ++step_;
  }
  std::vector<RecordedFrame> finish() {
    if (last_) frames_.push_back(std::move(*last_));
    return std::move(frames_);
  }

 private:
  WhiskerSurface surface_;
  const TaskConfig& task_;
  std::string title_;
  int every_, episode_, step_ = 0;
  std::vector<RecordedFrame> frames_;
  std::optional<RecordedFrame> last_;
};

io::ColourScale strain_scale(const std::vector<std::vector<RecordedFrame>>& seqs, const io::RenderConfig& c) {
  if (c.fixed_strain_range) return {c.strain_min_percent / 100.0, c.strain_max_percent / 100.0};
  double lo = 1e300, hi = -1e300;
  for (const auto& s : seqs)
    for (const RecordedFrame& f : s)
      for (float e : f.scene.strain)
        if (std::isfinite(e)) lo = std::min(lo, static_cast<double>(e)), hi = std::max(hi, static_cast<double>(e));
  if (!(lo <= hi)) return {0.0, 1e-3};
  if (hi - lo < 1e-6) lo -= 5e-7, hi += 5e-7;  // a flat field still gets a usable scale
  return {lo, hi};
}

}  // namespace

WhiskerSurface::WhiskerSurface(const fem::Model& model) {
  const fem::TetMesh& m = model.mesh;
  std::vector<std::array<int, 3>> chamber;
  for (const auto& faces : m.chamber_faces)
    for (const fem::Tri& t : faces) chamber.push_back(sorted(t));
  std::sort(chamber.begin(), chamber.end());
  std::vector<int> vertex_of(m.nodes.size(), -1);
  for (const fem::Tri& t : fem::boundary_faces(m)) {
    if (std::binary_search(chamber.begin(), chamber.end(), sorted(t))) continue;
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      int& v = vertex_of[static_cast<std::size_t>(t[k])];
      if (v < 0) {
        v = static_cast<int>(nodes_.size());
        nodes_.push_back(t[k]);
      }
      tri[k] = v;
    }
    triangles_.push_back(tri);
  }
  // Tets at each surface vertex, weighted by rest volume.
  std::vector<std::vector<std::pair<int, double>>> adj(nodes_.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const double vol = std::abs(fem::tet_volume(m, static_cast<int>(t)));
    for (int n : m.tets[t])
      if (const int v = vertex_of[static_cast<std::size_t>(n)]; v >= 0)
        adj[static_cast<std::size_t>(v)].push_back({static_cast<int>(t), vol});
  }
  adj_start_.push_back(0);
  for (const auto& a : adj) {
    double sum = 0.0;
    for (const auto& [t, w] : a) sum += w;
    for (const auto& [t, w] : a) {
      adj_tet_.push_back(t);
      adj_weight_.push_back(sum > 0.0 ? w / sum : 0.0);
    }
    adj_start_.push_back(static_cast<int>(adj_tet_.size()));
  }
  for (int n : model.base_nodes)
    base_radius_ = std::max(base_radius_, model.rest_positions.segment<2>(3 * n + 1).norm());
  length_ = model.length_mm;
}

io::SceneFrame WhiskerSurface::frame(const fem::Simulator& sim) const {
  io::SceneFrame f;
  const Eigen::VectorXd& x = sim.positions();
  const std::vector<double> strain = sim.element_axial_strain();
  f.vertices.resize(nodes_.size());
  f.strain.resize(nodes_.size());
  for (std::size_t v = 0; v < nodes_.size(); ++v) {
    f.vertices[v] = x.segment<3>(3 * nodes_[v]).cast<float>();
    double e = 0.0;
    for (int k = adj_start_[v]; k < adj_start_[v + 1]; ++k)
      e += adj_weight_[static_cast<std::size_t>(k)] * strain[static_cast<std::size_t>(adj_tet_[static_cast<std::size_t>(k)])];
    f.strain[v] = static_cast<float>(e);
  }
  f.triangles = triangles_;
  const double alpha = sim.scene().alpha_rad();
  const double tip_x = length_ * std::cos(alpha);
  f.plate_z_mm = sim.plate_z();
  f.plate_x0_mm = tip_x - 0.45 * length_;
  f.plate_x1_mm = tip_x + 0.25 * length_;
  f.plate_half_width_mm = std::max(25.0, 2.0 * base_radius_);
  f.base_angle_rad = alpha + sim.theta();
  f.base_radius_mm = base_radius_;
  const fem::Sensors s = sim.sensors();
  f.force_mN = s.contact_force_mN;
  // Point of application: the contact nodes weighted by their multipliers.
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double sum = 0.0;
  for (const auto& [node, lambda] : sim.contact_forces())
    if (lambda > 0.0) p += lambda * x.segment<3>(3 * node), sum += lambda;
  f.force_point_mm = sum > 0.0 ? Eigen::Vector3d(p / sum) : s.tip_position_mm;
  return f;
}

std::string design_title(int design, double p1_kPa, double p2_kPa) {
  const fem::Design d = fem::design_from_index(design);
  char buf[128];
  std::snprintf(buf, sizeof buf, "j%d {%d, %g mm, %g mm}  p = [%.3g, %.3g] kPa", design, d.n, d.chamber_length_mm,
                d.wall_mm, p1_kPa, d.n >= 2 ? p2_kPa : 0.0);
  return buf;
}

std::vector<RecordedFrame> record_episode(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                          const EpisodeSetup& setup, const Controller& controller, int every_steps,
                                          const std::string& title, int episode) {
  if (every_steps < 1) throw std::invalid_argument("record_episode: every_steps must be >= 1");
  FrameKeeper keep(*sims->model(setup.design), task, title, every_steps, episode);
  WhiskerEnv env(sims, task);
  env.set_episode(setup);
  env.set_recording(true);
  env.set_step_observer([&](const fem::Simulator& sim, const TraceRow& row) { keep.see(sim, row); });
  Eigen::VectorXd obs = env.reset(std::nullopt);
  Eigen::VectorXd a(1);
  for (;;) {
    a[0] = controller ? controller(obs) : 0.0;
    rl::StepResult r = env.step(a);
    if (r.done()) break;
    obs = std::move(r.obs);
  }
  return keep.finish();
}

std::vector<RecordedFrame> record_scenario(const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                                           const fem::SimScenario& sc, int every_steps, const std::string& title) {
  if (every_steps < 1) throw std::invalid_argument("record_scenario: every_steps must be >= 1");
  const auto model = sims->model(sc.design);
  FrameKeeper keep(*model, task, title, every_steps, 0);
  std::unique_ptr<fem::Simulator> sim = sims->acquire(sc.design);
  sim->reset();
  core::run_open_loop_scenario(*sim, sc, [&](int, int hold, const fem::StepResult& r) {
    if (r.ok()) keep.see(*sim, trace_row(sim->sensors(), hold, 0.0));
  });
  sims->release(sc.design, std::move(sim));
  return keep.finish();
}

int write_frames(const fs::path& dir, const std::vector<std::vector<RecordedFrame>>& seqs,
                 const io::RenderConfig& config, bool force) {
  if (seqs.empty() || seqs.size() > 2) throw std::invalid_argument("write_frames: one or two sequences");
  for (const auto& s : seqs)
    if (s.empty()) throw InputError(dir.string() + ": nothing to render (the episode failed before its first frame)");
  std::error_code ec;
  if (fs::exists(dir / "frame_0000.png", ec)) {
    if (!force)
      throw InputError(dir.string() + ": already holds frame_0000.png of an earlier render; choose another folder "
                       "or pass --force");
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (name.rfind("frame_", 0) == 0 && e.path().extension() == ".png") fs::remove(e.path(), ec);
    }
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the frames folder: " + ec.message());

  io::Renderer renderer(config.width, config.height);
  const int panels = static_cast<int>(seqs.size());
  std::vector<io::Camera> cameras;
  for (int i = 0; i < panels; ++i) {
    const io::PanelLayout l = io::panel_layout(i, panels, config.width, config.height);
    io::Camera cam = io::fit_camera(seqs[static_cast<std::size_t>(i)].front().scene, config.azimuth_deg,
                                    config.elevation_deg, config.fov_deg,
                                    static_cast<double>(l.scene.width) / l.scene.height);
    cam.distance_mm /= config.zoom;
    cameras.push_back(cam);
  }
  const io::ColourScale scale = strain_scale(seqs, config);
  io::RenderStyle style;
  style.scene.arrow_mm_per_mN = config.arrow_mm_per_mN;
  style.scene.force_arrow = config.arrow_mm_per_mN > 0.0;
  io::PngOptions png;
  png.compression = config.png_compression;
  std::size_t frames = 0;
  for (const auto& s : seqs) frames = std::max(frames, s.size());
  std::ofstream csv(dir / "frames.csv");
  csv << "frame,panel,episode,step,decision,t_s,theta_rad,F_mN,strain,tip_x_mm,tip_y_mm,tip_z_mm,plate_z_mm,in_band\n";
  std::vector<io::ScenePanel> p(static_cast<std::size_t>(panels));
  for (std::size_t k = 0; k < frames; ++k) {
    for (int i = 0; i < panels; ++i) {
      const auto& s = seqs[static_cast<std::size_t>(i)];
      const RecordedFrame& f = s[std::min(k, s.size() - 1)];
      p[static_cast<std::size_t>(i)] = {f.scene, f.overlay, cameras[static_cast<std::size_t>(i)]};
      const TraceRow& r = f.row;
      const bool band = io::band_state(r.force_mN, f.overlay.target_mN, f.overlay.band_fraction) == io::BandState::In;
      csv << k << ',' << i << ',' << f.episode << ',' << f.step << ',' << r.decision << ',' << io::CsvLog::num(r.t_s)
          << ',' << io::CsvLog::num(r.theta_rad) << ',' << io::CsvLog::num(r.force_mN) << ','
          << io::CsvLog::num(r.strain) << ',' << io::CsvLog::num(r.tip_mm.x()) << ','
          << io::CsvLog::num(r.tip_mm.y()) << ',' << io::CsvLog::num(r.tip_mm.z()) << ','
          << io::CsvLog::num(r.plate_z_mm) << ',' << (band ? 1 : 0) << '\n';
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.png", k);
    io::write_png((dir / name).string(), renderer.render(p, scale, style), png);
  }
  csv.close();
  if (!csv) throw FileError(file_error_text((dir / "frames.csv").string(), "cannot write", errno));
  return static_cast<int>(frames);
}

void render_run_frames(const fs::path& run_dir, const std::shared_ptr<SimulatorPool>& sims, const TaskConfig& task,
                       int eval_episodes, const io::RenderConfig& config, bool force) {
  const std::shared_ptr<const rl::Policy> policy = load_task_policy(run_dir / run_file::kPolicy, task);
  for (const char* which : {"best", "runner_up"}) {
    const std::optional<ResultDesign> result = read_result_design(run_dir, which);
    if (!result) continue;
    EpisodeSetup setup = result->setup;
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<RecordedFrame> frames;
    const std::string label = std::string(which) == "best" ? "d*: " : "runner-up: ";
    for (int k = 0; k < std::min(config.episodes, eval_episodes); ++k) {
      setup.plate_phase_rad = evaluation_phase(k, eval_episodes);
      std::vector<RecordedFrame> e =
          record_episode(sims, task, setup, episode_controller(policy), config.every_steps,
                         label + design_title(setup.design, setup.p1_kPa, setup.p2_kPa), k);
      frames.insert(frames.end(), std::make_move_iterator(e.begin()), std::make_move_iterator(e.end()));
    }
    const fs::path dir = run_dir / run_file::kFramesDir / which;
    const int n = write_frames(dir, {frames}, config, force);
    std::printf("codesign: rendered %d frames of %s (%dx%d) in %.1f s -> %s\n", n, which, config.width, config.height,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), dir.string().c_str());
    std::fflush(stdout);
  }
}

}  // namespace codesign::run
