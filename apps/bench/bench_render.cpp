// `codesign bench render [--config run.toml] [--frames N] [--width W] [--height H] [--gl-threads T]`
//
// Frames per second of the renderer on one core (Mesa's llvmpipe with LP_NUM_THREADS=T, set
// before the first context; default 0: no rasteriser threads, all work in the calling thread),
// on the frames of a real episode: design [sim].design at [sim].pressures_kPa with the base held still, one frame per simulation step. Three passes over
// the same frames, the median pass reported, for
//   ours:      vertex arrays, PNG at zlib level [render] png_compression with the "up" filter
//   baseline:  the whisker sent vertex by vertex (glBegin/glEnd), PNG with libpng's defaults
//              (zlib level 6, adaptive row filters) — measured in the same run
// with the render (GL draw + read-back + text) and the PNG writing timed separately, and the
// process CPU time over wall time (≈ 1 when one core does the work).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "commands.hpp"
#include "io/formats/png_file.hpp"
#include "io/render/render_osmesa.hpp"
#include "run/episode_render.hpp"
#include "run/run_config.hpp"

namespace codesign::app {

namespace {

namespace fs = std::filesystem;

struct BenchRenderOptions {
  std::string config;
  int frames = 100;
  int width = 1280, height = 720;
  int gl_threads = 0;  // 0: llvmpipe rasterises in the calling thread
};

struct Pass {
  double render_s = 0.0, png_s = 0.0, cpu_s = 0.0, wall_s = 0.0;
  std::uintmax_t bytes = 0;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

Pass run_pass(io::Renderer& r, const std::vector<run::RecordedFrame>& frames, const io::Camera& cam,
              const io::ColourScale& scale, const io::RenderStyle& style, const io::PngOptions& png,
              const fs::path& dir) {
  Pass p;
  const std::clock_t c0 = std::clock();
  const double w0 = now();
  int k = 0;
  for (const run::RecordedFrame& f : frames) {
    const io::ScenePanel panel{f.scene, f.overlay, cam};
    const double t0 = now();
    const io::RgbImage img = r.render({&panel, 1}, scale, style);
    const double t1 = now();
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", k++);
    io::write_png((dir / name).string(), img, png);
    p.png_s += now() - t1;
    p.render_s += t1 - t0;
    p.bytes += fs::file_size(dir / name);
  }
  p.wall_s = now() - w0;
  p.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return p;
}

int run_bench_render(const BenchRenderOptions& o) {
  // llvmpipe reads LP_NUM_THREADS when the first context is created.
  const std::string threads = std::to_string(o.gl_threads);
  ::setenv("LP_NUM_THREADS", threads.c_str(), 1);
  const run::RunConfig setup = run::read_run_config(o.config);
  io::RenderConfig rc = setup.render;
  rc.width = o.width;
  rc.height = o.height;
  rc.validate("command line");
  auto sims = std::make_shared<core::SimulatorPool>(setup.spec, setup.scene, setup.solver);
  const fem::SimScenario& sc = setup.scenario;
  core::EpisodeSetup es{sc.design, sc.pressures_kPa[0], sc.pressures_kPa[1], 0.0, 0.0};
  std::vector<run::RecordedFrame> frames =
      run::record_episode(sims, setup.task, es, nullptr, 1, run::design_title(es.design, es.p1_kPa, es.p2_kPa));
  if (static_cast<int>(frames.size()) > o.frames) frames.resize(static_cast<std::size_t>(o.frames));

  io::Renderer r(o.width, o.height);
  const io::PanelLayout l = io::panel_layout(0, 1, o.width, o.height);
  const io::Camera cam = io::fit_camera(frames.front().scene, rc.azimuth_deg, rc.elevation_deg, rc.fov_deg,
                                        static_cast<double>(l.scene.width) / l.scene.height);
  double lo = 1e300, hi = -1e300;
  for (const auto& f : frames)
    for (float e : f.scene.strain) lo = std::min(lo, static_cast<double>(e)), hi = std::max(hi, static_cast<double>(e));
  const io::ColourScale scale{lo, hi};
  io::RenderStyle ours, base;
  base.scene.vertex_arrays = false;
  io::PngOptions png_ours{rc.png_compression, false}, png_base{6, true};
  const fs::path dir = fs::temp_directory_path() / ("codesign_bench_render_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::printf("bench render: %s; %zu frames of design %d (%d surface triangles), %dx%d, LP_NUM_THREADS=%d\n",
              r.gl_description().c_str(), frames.size(), es.design,
              static_cast<int>(frames.front().scene.triangles.size()), o.width, o.height, o.gl_threads);
  (void)run_pass(r, {frames.begin(), frames.begin() + std::min<std::size_t>(5, frames.size())}, cam, scale, ours,
                 png_ours, dir);  // warm-up: shader compilation
  auto median = [&](const io::RenderStyle& style, const io::PngOptions& png) {
    std::vector<Pass> passes;
    for (int k = 0; k < 3; ++k) passes.push_back(run_pass(r, frames, cam, scale, style, png, dir));
    std::sort(passes.begin(), passes.end(), [](const Pass& a, const Pass& b) { return a.wall_s < b.wall_s; });
    return passes[1];
  };
  const Pass a = median(ours, png_ours);
  const Pass b = median(base, png_base);
  fs::remove_all(dir);
  const double n = static_cast<double>(frames.size());
  auto line = [&](const char* name, const Pass& p, int level) {
    std::printf("  %-9s render %6.2f ms/frame, PNG (level %d) %6.2f ms/frame, %5.0f kB/frame: %6.1f frames/s "
                "(render only %6.1f); CPU/wall %.2f\n",
                name, 1e3 * p.render_s / n, level, 1e3 * p.png_s / n, p.bytes / n / 1e3, n / p.wall_s,
                n / p.render_s, p.cpu_s / p.wall_s);
  };
  line("ours", a, png_ours.compression);
  line("baseline", b, 6);
  const double fps = n / a.wall_s;
  // On a shared machine the process gets less than a core (CPU/wall < 1); frames per CPU second
  // is then what one whole core would give.
  std::printf("  frames/s incl. PNG: %.1f wall, %.1f per CPU second (%.2fx the baseline's %.1f wall); "
              "goal >= 20 at 1280x720 on one core: %s\n",
              fps, n / a.cpu_s, b.wall_s / a.wall_s, n / b.wall_s,
              o.width == 1280 && o.height == 720 ? (fps >= 20.0 ? "met" : "NOT met") : "(other size)");
  return 0;
}

}  // namespace

void add_bench_render_command(CLI::App& bench, Runner& run) {
  auto opt = std::make_shared<BenchRenderOptions>();
  CLI::App* cmd = bench.add_subcommand("render", "Renderer frames/s (OSMesa + PNG) against a naive baseline");
  cmd->add_option("--config", opt->config, "run config (default: built-in defaults)");
  cmd->add_option("--frames", opt->frames, "frames per pass (of one 251-frame episode)")->check(CLI::Range(1, 100000));
  cmd->add_option("--width", opt->width, "image width")->check(CLI::Range(64, 4096));
  cmd->add_option("--height", opt->height, "image height")->check(CLI::Range(64, 4096));
  cmd->add_option("--gl-threads", opt->gl_threads, "llvmpipe rasteriser threads (LP_NUM_THREADS)")
      ->check(CLI::Range(0, 64));
  cmd->callback([opt, &run] { run = [opt] { return run_bench_render(*opt); }; });
}

}  // namespace codesign::app
