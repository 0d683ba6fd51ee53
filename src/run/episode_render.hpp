#pragma once
// Rendered PNG sequences of whisker episodes (docs/rendering.md): re-simulates an episode —
// the whisker task with a controller (WhiskerEnv, as the evaluation runs it), or an open-loop
// θ schedule (the [sim] scenario of `codesign sim`) — keeps a scene per rendered step, and
// draws them with io::Renderer into DIR/frame_0000.png, frame_0001.png, ... plus DIR/frames.csv
// (frame, episode, step, t, θ, F, ε, tip position, in band) so every image can be matched to
// the numbers. Two sequences can be drawn side by side (a comparison of two designs).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/evaluation.hpp"
#include "core/simulator_pool.hpp"
#include "core/task_config.hpp"
#include "core/whisker_env.hpp"
#include "fem/model.hpp"
#include "fem/simulator.hpp"
#include "io/config/fem_config.hpp"
#include "io/config/render_config.hpp"
#include "io/render/render_scene.hpp"
#include "rl/policy_file.hpp"

namespace codesign::run {

// The outer surface of a whisker model (boundary faces without the chamber walls) and the
// per-vertex strain: the volume-weighted mean of the axial strain of the tets at the node.
class WhiskerSurface {
 public:
  explicit WhiskerSurface(const fem::Model& model);
  // The scene of the simulator's current state (a simulator of the same model).
  io::SceneFrame frame(const fem::Simulator& sim) const;
  int vertex_count() const { return static_cast<int>(nodes_.size()); }
  int triangle_count() const { return static_cast<int>(triangles_.size()); }

 private:
  std::vector<int> nodes_;                        // surface vertex -> model node
  std::vector<std::array<int, 3>> triangles_;     // surface vertex indices
  std::vector<int> adj_start_, adj_tet_;          // CSR: tets at each surface vertex
  std::vector<double> adj_weight_;                // their volume shares (sum 1 per vertex)
  double base_radius_ = 0.0;
  double length_ = 0.0;
};

// One rendered step of an episode.
struct RecordedFrame {
  int episode = 0;
  int step = 0;                 // simulation steps since the settled state (0 = settled)
  core::TraceRow row;                 // t, θ, F, ε, tip, plate, action
  io::SceneFrame scene;
  io::FrameOverlay overlay;
};

// A closed-loop episode of the whisker task: `setup` (design, pressures, plate phase) run by
// `controller` (nullptr: the base held still), a frame after settling and every `every_steps`
// simulation steps after it, and the last step. `title` heads every frame's text.
std::vector<RecordedFrame> record_episode(const std::shared_ptr<core::SimulatorPool>& sims, const core::TaskConfig& task,
                                          const core::EpisodeSetup& setup, const core::Controller& controller, int every_steps,
                                          const std::string& title, int episode = 0);

// The open-loop scenario of `codesign sim` ([sim]: design, pressures, θ schedule, steps) on the
// simulators of `sims`; the band of the overlay is the task's.
std::vector<RecordedFrame> record_scenario(const std::shared_ptr<core::SimulatorPool>& sims, const core::TaskConfig& task,
                                           const fem::SimScenario& scenario, int every_steps, const std::string& title);

// Renders the sequences (1: one panel; 2: side by side, the shorter one holding its last frame)
// into DIR as frame_NNNN.png + frames.csv, with one camera per panel fitted to its first frame
// and one strain scale for all panels (config.strain_range). Creates DIR; refuses (InputError)
// if DIR already holds frame_0000.png unless `force`, in which case earlier frames are removed.
// Returns the number of frames written.
int write_frames(const std::filesystem::path& dir, const std::vector<std::vector<RecordedFrame>>& sequences,
                 const io::RenderConfig& config, bool force);

// "j21 {1, 28 mm, 2.5 mm}  p = [0.069, 0] kPa"
std::string design_title(int design, double p1_kPa, double p2_kPa);

// The end of a co-design run: re-runs the first config.episodes evaluation episodes of d* and
// of the runner-up (from DIR/result.toml) with the final policy (DIR/policy.bin) and renders
// them into DIR/frames/best/ and DIR/frames/runner_up/. eval_episodes: the evaluation's episode
// count (it sets the plate phases). Prints one line per design.
void render_run_frames(const std::filesystem::path& run_dir, const std::shared_ptr<core::SimulatorPool>& sims,
                       const core::TaskConfig& task, int eval_episodes, const io::RenderConfig& config, bool force);

}  // namespace codesign::run
