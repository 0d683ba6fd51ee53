// Rendering simulated episodes: the surface, the images against the simulated tip, and the
// frames against the evaluation's trace.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "base/errors.hpp"
#include "fem/mesh_ops.hpp"
#include "io/formats/png_file.hpp"
#include "io/render/render_osmesa.hpp"
#include "run/episode_render.hpp"

using namespace codesign;
using namespace codesign::core;
using namespace codesign::run;

namespace {

namespace fs = std::filesystem;

std::shared_ptr<SimulatorPool> pool() {
  fem::SceneConfig scene;
  scene.settle_steps = 5;
  return std::make_shared<SimulatorPool>(fem::WhiskerModelSpec{}, scene, fem::SolverConfig{});
}

TaskConfig short_task() {
  TaskConfig t;
  t.episode_steps = 25;
  t.action_hold_steps = 5;
  return t;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("codesign_epr_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

bool near(io::Rgb a, io::Rgb b) { return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) <= 6; }

}  // namespace

TEST(WhiskerSurface, IsTheClosedOuterSurface) {
  auto sims = pool();
  const auto model = sims->model(21);
  const WhiskerSurface surface(*model);
  auto sim = sims->acquire(21);
  sim->reset();
  const io::SceneFrame f = surface.frame(*sim);
  std::vector<fem::Tri> tris(f.triangles.begin(), f.triangles.end());
  EXPECT_EQ(fem::count_open_edges(tris), 0) << "outer surface without the cavity is closed";
  EXPECT_EQ(f.vertices.size(), f.strain.size());
  // The cavity walls are gone: boundary faces = outer faces + chamber faces.
  std::size_t chamber = 0;
  for (const auto& c : model->mesh.chamber_faces) chamber += c.size();
  EXPECT_EQ(f.triangles.size() + chamber, fem::boundary_faces(model->mesh).size());
  // Undeformed: strain 0 (rounding only), base angle α, plate below the tip region.
  for (float e : f.strain) EXPECT_NEAR(e, 0.0f, 1e-9f);
  EXPECT_NEAR(f.base_angle_rad, sim->scene().alpha_rad(), 1e-15);
  EXPECT_NEAR(f.base_radius_mm, 12.0, 0.1);  // default base diameter 24 mm
}

TEST(EpisodeRender, SilhouetteFollowsTheSimulatedTip) {
  auto sims = pool();
  const TaskConfig task = short_task();
  fem::SimScenario sc;
  sc.design = 21;
  sc.theta_deg = {0.0, -8.0};  // turn the base up by 8° over 10 steps: the tip rises ~14 mm
  sc.theta_hold_steps = 10;
  sc.steps = 20;
  const std::vector<RecordedFrame> frames = record_scenario(sims, task, sc, 20, "t");
  ASSERT_EQ(frames.size(), 2u);  // settled state and step 20
  constexpr int W = 640, H = 360;
  io::Renderer r(W, H);
  const io::PanelLayout l = io::panel_layout(0, 1, W, H);
  const io::Camera cam =
      io::fit_camera(frames[0].scene, 0.0, 0.0, 30.0, static_cast<double>(l.scene.width) / l.scene.height);
  io::RenderStyle style;
  style.overlay = false;
  style.scene.plate = style.scene.base = style.scene.force_arrow = false;
  double lowest[2], tip_y[2], tip_x[2], right[2];
  for (int k = 0; k < 2; ++k) {
    const io::ScenePanel p{frames[static_cast<std::size_t>(k)].scene, {}, cam};
    const io::RgbImage img = r.render({&p, 1}, {0.0, 0.01}, style);
    lowest[k] = right[k] = -1;
    for (int y = l.scene.y0; y < l.scene.y0 + l.scene.height; ++y)
      for (int x = l.scene.x0; x < l.scene.x0 + l.scene.width; ++x)
        if (!near(img.at(x, y), style.background)) lowest[k] = std::max(lowest[k], y + 0.5), right[k] = std::max(right[k], x + 0.5);
    const Eigen::Vector2d t = io::project_to_pixel(cam, l.scene, frames[static_cast<std::size_t>(k)].row.tip_mm);
    tip_y[k] = t.y();
    tip_x[k] = t.x();
  }
  const double moved = tip_y[1] - tip_y[0];
  ASSERT_LT(moved, -15.0) << "the tip rises on screen by more than 15 px";
  // The lowest and the rightmost silhouette pixels belong to the tip's end: they move with the
  // tip's sensor position (mean of the tip face), within 1.5 px of rasterisation plus 10 % for
  // the tip face turning with the base (the end's extreme points are not its centre).
  EXPECT_NEAR(lowest[1] - lowest[0], moved, 1.5 + 0.1 * std::abs(moved));
  EXPECT_NEAR(right[1] - right[0], tip_x[1] - tip_x[0], 1.5 + 0.1 * std::abs(moved));
}

TEST(EpisodeRender, FramesReproduceTheEvaluationEpisode) {
  auto sims = pool();
  const TaskConfig task = short_task();
  // A deterministic controller that reads the strain: the episode depends on the observations.
  const Controller c = [](const Eigen::VectorXd& obs) { return 0.3 - 2.0 * obs[5]; };
  const EpisodeSetup setup{21, 3.0, 0.0, 0.0, 0.0};
  EvaluationOptions eo;
  eo.episodes = 2;
  const DesignEvaluation e = evaluate_design(c, sims, task, setup, eo);
  EpisodeSetup first = setup;
  first.plate_phase_rad = evaluation_phase(0, 2);
  const std::vector<RecordedFrame> frames = record_episode(sims, task, first, c, 1, "x");
  ASSERT_EQ(frames.size(), e.trace.size());
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames[k].row.force_mN, e.trace[k].force_mN) << k;  // bit-identical: same simulation
    EXPECT_EQ(frames[k].row.theta_rad, e.trace[k].theta_rad) << k;
    EXPECT_EQ(frames[k].step, static_cast<int>(k));
    EXPECT_EQ(frames[k].overlay.force_mN, e.trace[k].force_mN);
  }
  // Every 10th step (0, 10, 20, ...) and the last one, wherever the episode ended.
  const std::vector<RecordedFrame> sparse = record_episode(sims, task, first, c, 10, "x");
  const int last = static_cast<int>(e.trace.size()) - 1;
  std::vector<int> steps, expected;
  for (const auto& f : sparse) steps.push_back(f.step);
  for (int k = 0; k <= last; k += 10) expected.push_back(k);
  if (last % 10 != 0) expected.push_back(last);
  EXPECT_EQ(steps, expected);
  const int n = static_cast<int>(expected.size());

  const fs::path dir = scratch("frames");
  io::RenderConfig rc;
  rc.width = 160;
  rc.height = 96;
  EXPECT_EQ(write_frames(dir, {sparse}, rc, false), n);
  for (int k = 0; k < n; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", k);
    const io::RgbImage img = io::read_png((dir / name).string());
    EXPECT_EQ(img.width, 160);
    EXPECT_EQ(img.height, 96);
  }
  char after[32];
  std::snprintf(after, sizeof after, "frame_%04d.png", n);
  EXPECT_FALSE(fs::exists(dir / after));
  std::ifstream csv(dir / "frames.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("frame,panel,episode,step", 0), 0u);
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, n);
  // An earlier render is kept unless forced.
  EXPECT_THROW(write_frames(dir, {sparse}, rc, false), InputError);
  EXPECT_EQ(write_frames(dir, {sparse}, rc, true), n);
  // Side by side: two panels, the shorter sequence holds its last frame.
  const fs::path two = scratch("two");
  EXPECT_EQ(write_frames(two, {sparse, {sparse.front()}}, rc, false), n);
  fs::remove_all(dir);
  fs::remove_all(two);
}
