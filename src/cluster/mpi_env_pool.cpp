#include "cluster/mpi_env_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "base/seconds_since.hpp"
#include "cluster/mesh_messages.hpp"
#include "cluster/mpi_wait.hpp"
#include "cluster/rollout_messages.hpp"
#include "fem/design.hpp"

namespace codesign::cluster {

namespace {

// Rank 0 -> rank r: a command header {command, flag}, then its payload (if any), all tag kCommand
// or kPayload; rank r -> rank 0: the reply (kReply) and, after a step, the end reasons (kReasons).
// After kRollout rank r gets two payloads (its setups; gamma, the batch's width and its places),
// then two broadcasts from rank 0 (the parameters, the normal draws); it answers with its record
// (kTagReply: floats, then doubles; kTagReasons). Around a start and a rollout the designs' meshes
// travel (kTagMeshes, pack_meshes): after the setups (and the places) rank 0 sends each rank the
// meshes of the designs it gets without holding them, as far as rank 0 has them; after its answer
// each rank sends back the meshes it made itself meanwhile. Both messages always go (an empty one
// holds a count of 0). During a whole rollout a rank that has run its share sends each other rank on
// its machine a note (kTagDone, one int), which they take up between environments (LendingRound).
// kPrestart carries the same two payloads and the meshes as kRollout; the rank starts its share
// then and keeps the first observations; a later kRollout with flag -n_steps (negative) means
// "your share is started": only the two broadcasts follow.
enum Command : int { kStop = 0, kStart = 1, kStep = 2, kTimes = 3, kPing = 4, kCosts = 5, kRollout = 6, kPrestart = 7 };
constexpr int kTagCommand = 101, kTagPayload = 102, kTagReply = 103, kTagReasons = 104, kTagMeshes = 105, kTagDone = 106;

void send_doubles(const std::vector<double>& v, int to, int tag) {
  check(MPI_Send(v.data(), static_cast<int>(v.size()), MPI_DOUBLE, to, tag, MPI_COMM_WORLD), "send");
}

void recv_into(void* data, int count, MPI_Datatype type, int from, int tag, MPI_Status* status, const char* what) {
  MPI_Request request;
  check(MPI_Irecv(data, count, type, from, tag, MPI_COMM_WORLD, &request), what);
  wait_without_spinning(request, status, what);
}

// n numbers of MPI type `type` (T's) from `from`; std::runtime_error for another count.
template <class T>
std::vector<T> recv_numbers(std::size_t n, MPI_Datatype type, int from, int tag) {
  std::vector<T> v(n);
  MPI_Status st;
  recv_into(v.data(), static_cast<int>(n), type, from, tag, &st, "receive");
  int got = 0;
  MPI_Get_count(&st, type, &got);
  if (static_cast<std::size_t>(got) != n)
    throw std::runtime_error("MPI rollout backend: a message of " + std::to_string(got) + " numbers where " +
                             std::to_string(n) + " were expected");
  return v;
}

std::vector<double> recv_doubles(std::size_t n, int from, int tag) {
  return recv_numbers<double>(n, MPI_DOUBLE, from, tag);
}

std::vector<float> recv_floats(std::size_t n, int from, int tag) { return recv_numbers<float>(n, MPI_FLOAT, from, tag); }

void send_command(int to, Command c, int flag) {
  const int header[2] = {c, flag};
  check(MPI_Send(header, 2, MPI_INT, to, kTagCommand, MPI_COMM_WORLD), "send a command");
}

// A message whose length the receiver does not know, into a container C of MPI type `type` (a
// std::string of MPI_CHAR, a std::vector<double> of MPI_DOUBLE). Each such message follows another
// of the same sender at once (the end reasons the step's numbers, the meshes the setups or the
// record), so the blocking probe waits no longer than an exchange.
template <class C>
C recv_unsized(int from, int tag, MPI_Datatype type, const char* what) {
  MPI_Status st;
  check(MPI_Probe(from, tag, MPI_COMM_WORLD, &st), "probe");
  int n = 0;
  MPI_Get_count(&st, type, &n);
  C c(static_cast<std::size_t>(n), typename C::value_type{});
  check(MPI_Recv(c.data(), n, type, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), what);
  return c;
}

std::string recv_string(int from, int tag) {
  return recv_unsized<std::string>(from, tag, MPI_CHAR, "receive the end reasons");
}

std::vector<DesignMesh> recv_meshes(int from) {
  return unpack_meshes(recv_unsized<std::vector<double>>(from, kTagMeshes, MPI_DOUBLE, "receive meshes"));
}

// The meshes of `designs` from `sims` (each has its model there) as one message.
std::vector<double> pack_held_meshes(core::SimulatorPool& sims, const std::vector<int>& designs) {
  std::vector<std::shared_ptr<const fem::Model>> models;
  std::vector<const fem::TetMesh*> meshes;
  for (int d : designs) {
    models.push_back(sims.model(d));
    meshes.push_back(&models.back()->mesh);
  }
  return pack_meshes(designs, meshes);
}

// Builds the models of received meshes in `sims` (a design `sims` already has is skipped).
void adopt_meshes(core::SimulatorPool& sims, std::vector<DesignMesh> meshes) {
  for (DesignMesh& m : meshes) sims.adopt_mesh(m.design, std::move(m.mesh));
}

// Sends without holding a core while the receiver is not there yet (a whole rollout's record may wait
// for rank 0 to finish its own share, and rank 0 may be using this rank's core meanwhile).
void send_without_spinning(const void* data, std::size_t count, MPI_Datatype type, int to, int tag, const char* what) {
  MPI_Request request;
  check(MPI_Isend(data, static_cast<int>(count), type, to, tag, MPI_COMM_WORLD, &request), what);
  wait_without_spinning(request, MPI_STATUS_IGNORE, what);
}

// A rank's pool between whole rollouts (and in step-by-step ones): on the rank's own threads, which
// the pool must hold.
void use_own_threads(core::ThreadEnvPool& pool, const Lending& lending, const char* who) {
  if (lending.own_threads > pool.threads())
    throw std::invalid_argument(std::string(who) + ": the rank's pool has fewer threads than its own");
  pool.set_threads_in_use(threads_in_use(lending.own_threads, 0, pool.threads()));
}

// One whole rollout's lending on one rank (lent_threads.hpp). Made before the rank's share starts:
// the pool steps on the rank's own threads and asks poll() between environments (its lender), so
// each other rank of the machine whose note has come lends its threads from the next environment
// on. done() once the share is run (a note to each of them); finish() after the rank's record: it
// waits for the note of every other rank of the machine, so none is left over for the next
// rollout, and puts the pool back on the rank's own threads.
class LendingRound {
 public:
  LendingRound(core::ThreadEnvPool& pool, const Lending& lending)
      : pool_(pool), lending_(lending), heard_(lending.peers.size(), 0) {
    use_own_threads(pool_, lending_, "LendingRound");
    if (!heard_.empty()) pool_.set_lender([this] { return poll(); });
  }
  ~LendingRound() { pool_.set_lender({}); }
  LendingRound(const LendingRound&) = delete;
  LendingRound& operator=(const LendingRound&) = delete;

  void done() {
    if (lent_since_ >= 0.0) lent_s_ += MPI_Wtime() - lent_since_;
    lent_since_ = -1.0;
    pool_.set_lender({});
    notes_.assign(lending_.peers.size(), MPI_REQUEST_NULL);
    for (std::size_t k = 0; k < notes_.size(); ++k)
      check(MPI_Isend(&kNote, 1, MPI_INT, lending_.peers[k], kTagDone, MPI_COMM_WORLD, &notes_[k]), "send a note");
  }

  void finish() {
    for (std::size_t k = 0; k < heard_.size(); ++k)
      if (!heard_[k]) receive(k);
    for (MPI_Request& r : notes_) wait_without_spinning(r, MPI_STATUS_IGNORE, "send a note");
    use_own_threads(pool_, lending_, "LendingRound");
  }

  // Wall seconds the share was stepped on more threads than the rank's own.
  double lent_seconds() const { return lent_s_; }

 private:
  std::size_t own() const { return threads_in_use(lending_.own_threads, 0, pool_.threads()); }

  // The threads the pool may use now: the rank's own and those of the ranks whose notes have come.
  std::size_t poll() {
    for (std::size_t k = 0; k < heard_.size(); ++k) {
      if (heard_[k]) continue;
      int flag = 0;
      check(MPI_Iprobe(lending_.peers[k], kTagDone, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE), "probe for a rank's note");
      if (flag) receive(k);
    }
    const std::size_t n = threads_in_use(lending_.own_threads, finished_, pool_.threads());
    if (n > own() && lent_since_ < 0.0) lent_since_ = MPI_Wtime();
    return n;
  }

  void receive(std::size_t k) {
    int note = 0;
    recv_into(&note, 1, MPI_INT, lending_.peers[k], kTagDone, MPI_STATUS_IGNORE, "receive a note");
    heard_[k] = 1;
    ++finished_;
  }

  static constexpr int kNote = 1;
  core::ThreadEnvPool& pool_;
  const Lending& lending_;
  std::vector<char> heard_;
  std::size_t finished_ = 0;
  std::vector<MPI_Request> notes_;
  double lent_since_ = -1.0, lent_s_ = 0.0;
};

// A rank's part after its answer: the meshes it made since the last one.
void send_own_meshes(core::ThreadEnvPool& local) {
  core::SimulatorPool& sims = local.simulators();
  send_doubles(pack_held_meshes(sims, sims.take_meshed()), 0, kTagMeshes);
}

std::vector<double> columns(const Eigen::MatrixXd& m, EnvSlice s) {
  std::vector<double> v(static_cast<std::size_t>(m.rows()) * s.count);
  Eigen::Map<Eigen::MatrixXd>(v.data(), m.rows(), static_cast<Eigen::Index>(s.count)) =
      m.middleCols(static_cast<Eigen::Index>(s.first), static_cast<Eigen::Index>(s.count));
  return v;
}

// normals[k] (a x width each) as one array, decision after decision.
std::vector<double> flat_normals(const std::vector<Eigen::MatrixXd>& normals, std::size_t a, std::size_t width) {
  std::vector<double> v;
  v.reserve(normals.size() * a * width);
  for (const Eigen::MatrixXd& z : normals) {
    if (z.rows() != static_cast<Eigen::Index>(a) || z.cols() != static_cast<Eigen::Index>(width))
      throw std::invalid_argument("MpiEnvPool::rollout: each decision's normals must be act_dim x environments");
    v.insert(v.end(), z.data(), z.data() + z.size());
  }
  return v;
}

}  // namespace

MpiEnvPool::MpiEnvPool(std::unique_ptr<core::ThreadEnvPool> local, std::size_t n_envs, int ranks, Lending lending)
    : local_(std::move(local)), n_envs_(n_envs), ranks_(ranks), slices_(env_slices(n_envs, ranks)),
      lending_(std::move(lending)) {
  if (!local_ || local_->size() != slices_[0].count)
    throw std::invalid_argument("MpiEnvPool: rank 0's pool must hold its slice of " + std::to_string(slices_[0].count) +
                                " environments");
  use_own_threads(*local_, lending_, "MpiEnvPool");
  if (local_->threads() < 2) update_pool_ = std::make_unique<rl::ThreadPool>(2);
  result_ = rl::VecStepResult(spec().observation.dim(), n_envs);
  placed_ = rl::VecStepResult(spec().observation.dim(), n_envs);
  last_in_band_.assign(n_envs, 0);
  placed_in_band_.assign(n_envs, 0);
  order_.resize(n_envs);
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  design_cost_.assign(fem::kDesignCount, std::numeric_limits<double>::quiet_NaN());
  build_.held.assign(slices_.size(), std::vector<int>(fem::kDesignCount, 0));
  mesh_sends_.resize(slices_.size());
}

MpiEnvPool::~MpiEnvPool() {
  for (int r = 1; r < ranks_; ++r) {
    const int header[2] = {kStop, 0};
    MPI_Send(header, 2, MPI_INT, r, kTagCommand, MPI_COMM_WORLD);  // no throw from a destructor
  }
}

std::vector<double> MpiEnvPool::work_since_start() const {
  // After a prestart the ranks' counters hold the next starts: the last rollout's, read before them.
  if (!prestart_setups_.empty()) return work_before_prestart_;
  std::vector<double> work(n_envs_);
  const std::vector<double> mine = local_->work_since_start();
  for (std::size_t k = 0; k < mine.size(); ++k) work[order_[k]] = mine[k];
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kCosts, 0);
    const std::vector<double> v = recv_doubles(slices_[r].count, r, kTagReply);
    for (std::size_t k = 0; k < v.size(); ++k) work[order_[slices_[r].first + k]] = v[k];
  }
  return work;
}

double MpiEnvPool::imbalance(const std::vector<double>& work) const {
  if (work.size() != n_envs_) throw std::invalid_argument("MpiEnvPool::imbalance: one figure per environment");
  const std::vector<std::size_t>& order = prestart_setups_.empty() ? order_ : order_before_prestart_;
  double busiest = 0.0, total = 0.0;
  for (const EnvSlice& sl : slices_) {
    double w = 0.0;
    for (std::size_t j = sl.first; j < sl.first + sl.count; ++j) w += work[order[j]];
    busiest = std::max(busiest, w);
    total += w;
  }
  return total > 0.0 ? busiest * ranks_ / total : 1.0;
}

// What each design cost in the iteration that just ended (settle and step CPU seconds of its
// environment; the mean where several environments had it). build_.design still holds that
// iteration's designs: assign() calls this before it sets the next ones.
void MpiEnvPool::learn_costs(const std::vector<double>& work) {
  std::vector<double> sum(design_cost_.size(), 0.0), count(design_cost_.size(), 0.0);
  for (std::size_t i = 0; i < n_envs_; ++i) {
    const int d = build_.design[i];
    if (d < 0 || d >= static_cast<int>(design_cost_.size())) continue;
    sum[static_cast<std::size_t>(d)] += work[i];
    count[static_cast<std::size_t>(d)] += 1.0;
  }
  for (std::size_t d = 0; d < sum.size(); ++d)
    if (count[d] > 0.0) design_cost_[d] = sum[d] / count[d];
}

std::vector<core::EpisodeSetup> MpiEnvPool::assign(const std::vector<core::EpisodeSetup>& setups,
                                                   const std::vector<double>* work) {
  if (setups.size() != n_envs_) throw std::invalid_argument("MpiEnvPool::start: one setup per environment");
  if (starts_ > 0) learn_costs(work ? *work : work_since_start());
  // Predicted cost of each environment (predict_costs). Before any design is known (the first
  // start) the slices stay contiguous.
  build_.design.resize(n_envs_);
  for (std::size_t i = 0; i < n_envs_; ++i) build_.design[i] = setups[i].design;
  const std::vector<double> predicted = predict_costs(design_cost_, build_.design);
  // What a rank builds for a design new to it: rank 0's own builds so far, per model and per
  // simulator (all ranks run the same code; before rank 0 has built anything, nothing). On nodes
  // of different speeds rank 0's seconds stand for every rank's: a prediction, never a result.
  // Designs whose mesh rank 0 holds (its own, or sent by a rank that made it) cost another rank
  // only the model from the mesh (its seconds: rank 0's own such builds so far).
  const core::SimulatorPool& sims = local_->simulators();
  const core::SimulatorPool::BuildStats built = sims.build_stats();
  build_.model = built.seconds_per_model();
  build_.simulator = built.seconds_per_simulator();
  build_.model_from_mesh = built.seconds_per_adopted();
  build_.meshed.assign(fem::kDesignCount, 0);
  for (int d = 0; d < fem::kDesignCount; ++d) build_.meshed[static_cast<std::size_t>(d)] = sims.has_model(d) ? 1 : 0;
  if (!predicted.empty() && share_by_cost_) order_ = assign_by_cost(predicted, slices_, pinned_, build_);
  // Each rank's designs it holds no simulator of (so no model: a rank keeps what it built) and
  // whose mesh rank 0 has: their meshes go with the setups.
  for (std::size_t r = 1; r < slices_.size(); ++r) {
    std::vector<int>& send = mesh_sends_[r];
    send.clear();
    const std::vector<int>& held = build_.held[r];
    for (std::size_t j = slices_[r].first; j < slices_[r].first + slices_[r].count; ++j) {
      const int d = build_.design[order_[j]];
      if (d < 0 || d >= fem::kDesignCount) continue;
      const auto k = static_cast<std::size_t>(d);
      if (!build_.meshed[k] || (k < held.size() && held[k] > 0)) continue;
      if (std::find(send.begin(), send.end(), d) == send.end()) send.push_back(d);
    }
    meshes_sent_ += static_cast<int>(send.size());
  }
  record_held(order_, slices_, build_);
  ++starts_;
  if (!std::is_sorted(order_.begin(), order_.end())) ++reassigned_;  // a sorted permutation is the identity
  std::vector<core::EpisodeSetup> placed(n_envs_);
  for (std::size_t j = 0; j < n_envs_; ++j) placed[j] = setups[order_[j]];
  return placed;
}

Eigen::MatrixXd MpiEnvPool::start(const std::vector<core::EpisodeSetup>& setups) {
  const std::vector<core::EpisodeSetup> placed = assign(setups);
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kStart, 0);
    send_doubles(pack_setups(placed, slices_[r].first, slices_[r].count), r, kTagPayload);
    send_meshes_to(r);
  }
  const std::vector<core::EpisodeSetup> mine(placed.begin(), placed.begin() + static_cast<std::ptrdiff_t>(slices_[0].count));
  const Eigen::Index d = static_cast<Eigen::Index>(spec().observation.dim());
  Eigen::MatrixXd obs(d, static_cast<Eigen::Index>(n_envs_));
  const Eigen::MatrixXd first = local_->start(mine);
  for (std::size_t k = 0; k < slices_[0].count; ++k)
    obs.col(static_cast<Eigen::Index>(order_[k])) = first.col(static_cast<Eigen::Index>(k));
  const auto waiting = std::chrono::steady_clock::now();
  for (int r = 1; r < ranks_; ++r) {
    const EnvSlice s = slices_[r];
    const std::vector<double> v = recv_doubles(static_cast<std::size_t>(d) * s.count, r, kTagReply);
    const Eigen::Map<const Eigen::MatrixXd> got(v.data(), d, static_cast<Eigen::Index>(s.count));
    for (std::size_t k = 0; k < s.count; ++k)
      obs.col(static_cast<Eigen::Index>(order_[s.first + k])) = got.col(static_cast<Eigen::Index>(k));
    receive_meshes_from(r);
  }
  start_wait_s_ += seconds_since(waiting);
  return obs;
}

const rl::VecStepResult& MpiEnvPool::step(const Eigen::MatrixXd& actions, bool restart) {
  if (actions.cols() != static_cast<Eigen::Index>(n_envs_))
    throw std::invalid_argument("MpiEnvPool::step: one action column per environment");
  placed_actions_.resize(actions.rows(), actions.cols());
  for (std::size_t j = 0; j < n_envs_; ++j)
    placed_actions_.col(static_cast<Eigen::Index>(j)) = actions.col(static_cast<Eigen::Index>(order_[j]));
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kStep, restart ? 1 : 0);
    send_doubles(columns(placed_actions_, slices_[r]), r, kTagPayload);
  }
  // Rank 0's share, while the other ranks step theirs.
  const auto n0 = static_cast<Eigen::Index>(slices_[0].count);
  const rl::VecStepResult& mine = local_->step(placed_actions_.leftCols(n0), restart);
  placed_.obs.leftCols(n0) = mine.obs;
  placed_.rewards.head(n0) = mine.rewards;
  for (std::size_t j = 0; j < slices_[0].count; ++j) {
    placed_.terminated[j] = mine.terminated[j];
    placed_.truncated[j] = mine.truncated[j];
    placed_.terminal_obs[j] = mine.terminal_obs[j];
    placed_.reasons[j] = mine.reasons[j];
    if (mine.done(j)) placed_in_band_[j] = local_->last_in_band(j);
  }
  const std::size_t d = spec().observation.dim();
  const auto waiting = std::chrono::steady_clock::now();
  for (int r = 1; r < ranks_; ++r) {
    const EnvSlice s = slices_[r];
    const std::vector<double> v = recv_doubles(s.count * (kStepFields + 2 * d), r, kTagReply);
    const std::vector<std::string> reasons = split_reasons(recv_string(r, kTagReasons), s.count);
    unpack_step(v, d, s.first, placed_, placed_in_band_);
    for (std::size_t k = 0; k < s.count; ++k) placed_.reasons[s.first + k] = reasons[k];
  }
  step_wait_s_ += seconds_since(waiting);
  // Back to the environments' own order.
  for (std::size_t j = 0; j < n_envs_; ++j) {
    const std::size_t i = order_[j];
    result_.obs.col(static_cast<Eigen::Index>(i)) = placed_.obs.col(static_cast<Eigen::Index>(j));
    result_.rewards(static_cast<Eigen::Index>(i)) = placed_.rewards(static_cast<Eigen::Index>(j));
    result_.terminated[i] = placed_.terminated[j];
    result_.truncated[i] = placed_.truncated[j];
    result_.terminal_obs[i] = std::move(placed_.terminal_obs[j]);
    placed_.terminal_obs[j].reset();
    result_.reasons[i] = std::move(placed_.reasons[j]);
    placed_.reasons[j].clear();
    if (placed_.done(j)) last_in_band_[i] = placed_in_band_[j];
  }
  return result_;
}

bool MpiEnvPool::prestarts(int r) const {
  if (r < 1 || r >= ranks_) return false;
  const bool peer = std::find(lending_.peers.begin(), lending_.peers.end(), r) != lending_.peers.end();
  // A rank of rank 0's machine has cores of its own during the update only if rank 0's own
  // threads hold the update's two (own_threads 0: rank 0's pool is the machine's).
  return !peer || lending_.own_threads >= 2;
}

void MpiEnvPool::send_share(int r, int command, int flag, const std::vector<core::EpisodeSetup>& placed, double gamma) {
  send_command(r, static_cast<Command>(command), flag);
  send_doubles(pack_setups(placed, slices_[r].first, slices_[r].count), r, kTagPayload);
  std::vector<double> where{gamma, static_cast<double>(n_envs_)};
  for (std::size_t j = slices_[r].first; j < slices_[r].first + slices_[r].count; ++j)
    where.push_back(static_cast<double>(order_[j]));
  send_doubles(where, r, kTagPayload);
  send_meshes_to(r);
}

void MpiEnvPool::prestart(const std::vector<core::EpisodeSetup>& setups) {
  if (!prestart_setups_.empty()) throw std::logic_error("MpiEnvPool::prestart: the last prestart's rollout has not run");
  bool any = false;
  for (int r = 1; r < ranks_; ++r) any = any || prestarts(r);
  if (!any) return;
  work_before_prestart_ = work_since_start();
  order_before_prestart_ = order_;
  prestart_placed_ = assign(setups, &work_before_prestart_);
  prestart_setups_ = setups;
  // gamma travels with the rollout's broadcasts' command instead; the places are fixed now.
  for (int r = 1; r < ranks_; ++r)
    if (prestarts(r)) send_share(r, kPrestart, 0, prestart_placed_, 0.0);
}

core::ShareRollout MpiEnvPool::rollout(const std::vector<core::EpisodeSetup>& setups, const rl::ActorCritic& model,
                                       const std::vector<Eigen::MatrixXd>& normals, double gamma) {
  const bool early = !prestart_setups_.empty();
  if (early && prestart_setups_ != setups)
    throw std::invalid_argument("MpiEnvPool::rollout: other setups than the prestart's");
  const std::vector<core::EpisodeSetup> placed = early ? prestart_placed_ : assign(setups);
  prestart_setups_.clear();
  prestart_placed_.clear();
  if (early) ++prestarted_rollouts_;
  const int n_steps = static_cast<int>(normals.size());
  const std::size_t d = spec().observation.dim(), a = spec().action.dim();
  const auto places_of = [&](const EnvSlice& sl) {
    return std::vector<std::size_t>(order_.begin() + static_cast<std::ptrdiff_t>(sl.first),
                                    order_.begin() + static_cast<std::ptrdiff_t>(sl.first + sl.count));
  };
  for (int r = 1; r < ranks_; ++r) {
    if (early && prestarts(r)) {  // its share was sent and started by the prestart
      send_command(r, kRollout, -n_steps);
      send_doubles({gamma}, r, kTagPayload);
    } else {
      send_share(r, kRollout, n_steps, placed, gamma);
    }
  }
  if (ranks_ > 1) {
    std::vector<float> params = pack_policy(model);
    check(MPI_Bcast(params.data(), static_cast<int>(params.size()), MPI_FLOAT, 0, MPI_COMM_WORLD), "broadcast the policy");
    std::vector<double> z = flat_normals(normals, a, n_envs_);
    check(MPI_Bcast(z.data(), static_cast<int>(z.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD), "broadcast the draws");
  }
  ++rollouts_;
  const std::vector<core::EpisodeSetup> mine(placed.begin(), placed.begin() + static_cast<std::ptrdiff_t>(slices_[0].count));
  const std::vector<std::size_t> my_places = places_of(slices_[0]);
  core::ShareRollout all = core::empty_share(n_steps, n_envs_, d, a);
  LendingRound lending(*local_, lending_);
  const core::ShareRollout own = core::run_share(*local_, mine, model, cache_, my_places, n_envs_, normals, gamma);
  lending.done();
  core::place_share(own, my_places, all);
  all.policy_s = own.policy_s;
  const auto waiting = std::chrono::steady_clock::now();
  for (int r = 1; r < ranks_; ++r) {
    const std::size_t w = slices_[r].count;
    PackedShare p;
    p.floats = recv_floats(share_floats(n_steps, w, d, a), r, kTagReply);
    p.doubles = recv_doubles(share_doubles(n_steps, w), r, kTagReply);
    p.reasons = recv_string(r, kTagReasons);
    core::place_share(unpack_share(p, n_steps, w, d, a), places_of(slices_[r]), all);
    receive_meshes_from(r);
  }
  rollout_wait_s_ += seconds_since(waiting);
  lending.finish();
  lent_s_ += lending.lent_seconds();
  return all;
}

void MpiEnvPool::send_meshes_to(int r) {
  send_doubles(pack_held_meshes(local_->simulators(), mesh_sends_[static_cast<std::size_t>(r)]), r, kTagMeshes);
}

void MpiEnvPool::receive_meshes_from(int r) {
  std::vector<DesignMesh> meshes = recv_meshes(r);
  meshes_received_ += static_cast<int>(meshes.size());
  adopt_meshes(local_->simulators(), std::move(meshes));
}

// The settle, step and build CPU seconds of ranks 1.., and their wall seconds on lent threads (one
// query each).
std::array<double, 4> MpiEnvPool::remote_seconds() const {
  std::array<double, 4> sum{0.0, 0.0, 0.0, 0.0};
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kTimes, 0);
    const std::vector<double> v = recv_doubles(sum.size(), r, kTagReply);
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += v[k];
  }
  return sum;
}

double MpiEnvPool::settle_seconds() const { return local_->settle_seconds() + remote_seconds()[0]; }

double MpiEnvPool::step_seconds() const { return local_->step_seconds() + remote_seconds()[1]; }

double MpiEnvPool::build_seconds() const { return local_->build_seconds() + remote_seconds()[2]; }

double MpiEnvPool::lent_seconds_of_all_ranks() const { return lent_s_ + remote_seconds()[3]; }

void MpiEnvPool::set_step_observer(std::size_t i, StepObserver observer, int every) {
  if (i >= slices_[0].count)
    throw std::invalid_argument("MpiEnvPool: environment " + std::to_string(i) +
                                " is stepped on another rank; live telemetry follows rank 0's environments only");
  // Place i on rank 0 steps environment i from the next start() on (pinned); set before the first
  // start(), as the run does, it follows environment i throughout.
  local_->set_step_observer(i, observer, every);
  const bool on = observer && every > 0;
  const auto at = std::find(pinned_.begin(), pinned_.end(), i);
  if (on && at == pinned_.end()) pinned_.push_back(i);
  if (!on && at != pinned_.end()) pinned_.erase(at);
}

double time_exchanges(int ranks, std::size_t out_doubles, std::size_t in_doubles, int repeats) {
  if (ranks < 2 || repeats < 1) return 0.0;
  const std::vector<double> out(out_doubles, 0.0);
  const double t0 = MPI_Wtime();
  for (int k = 0; k < repeats; ++k)
    for (int r = 1; r < ranks; ++r) {
      send_command(r, kPing, static_cast<int>(in_doubles));
      send_doubles(out, r, kTagPayload);
      recv_doubles(in_doubles, r, kTagReply);
      recv_string(r, kTagReasons);
    }
  return (MPI_Wtime() - t0) / (static_cast<double>(repeats) * (ranks - 1));
}

void serve_env_pool(core::ThreadEnvPool& local, rl::ActorCritic* model, const Lending& lending) {
  const std::size_t n = local.size(), a = local.spec().action.dim();
  use_own_threads(local, lending, "serve_env_pool");
  double lent_s = 0.0;  // wall seconds of whole rollouts stepped on lent threads
  rl::ActorCritic::InferenceCache cache;
  struct Started {  // a share started by kPrestart: its first observations and its places
    bool ready = false;
    Eigen::MatrixXd obs;
    std::vector<double> where;
  } started;
  for (;;) {
    int header[2] = {0, 0};
    recv_into(header, 2, MPI_INT, 0, kTagCommand, MPI_STATUS_IGNORE, "receive a command");
    switch (header[0]) {
      case kStop:
        return;
      case kStart: {
        const std::vector<core::EpisodeSetup> setups = unpack_setups(recv_doubles(n * kSetupFields, 0, kTagPayload));
        adopt_meshes(local.simulators(), recv_meshes(0));
        const Eigen::MatrixXd obs = local.start(setups);
        send_doubles(std::vector<double>(obs.data(), obs.data() + obs.size()), 0, kTagReply);
        send_own_meshes(local);
        break;
      }
      case kStep: {
        const std::vector<double> v = recv_doubles(n * a, 0, kTagPayload);
        const Eigen::MatrixXd actions = Eigen::Map<const Eigen::MatrixXd>(v.data(), static_cast<Eigen::Index>(a),
                                                                          static_cast<Eigen::Index>(n));
        const rl::VecStepResult& r = local.step(actions, header[1] != 0);
        std::vector<int> in_band(n, 0);
        for (std::size_t i = 0; i < n; ++i)
          if (r.done(i)) in_band[i] = local.last_in_band(i);
        send_doubles(pack_step(r, in_band), 0, kTagReply);
        const std::string reasons = join_reasons(r.reasons);
        check(MPI_Send(reasons.data(), static_cast<int>(reasons.size()), MPI_CHAR, 0, kTagReasons, MPI_COMM_WORLD),
              "send the end reasons");
        break;
      }
      case kPrestart: {
        if (!model) throw std::runtime_error("MPI rollout backend: a whole rollout asked of a rank without a feed-forward model");
        const std::vector<core::EpisodeSetup> setups = unpack_setups(recv_doubles(n * kSetupFields, 0, kTagPayload));
        started.where = recv_doubles(2 + n, 0, kTagPayload);
        adopt_meshes(local.simulators(), recv_meshes(0));
        started.obs = local.start(setups);
        started.ready = true;
        break;
      }
      case kRollout: {
        const bool early = header[1] < 0;
        const int n_steps = early ? -header[1] : header[1];
        if (early && !started.ready) throw std::runtime_error("MPI rollout backend: a rollout of a share not started");
        std::vector<core::EpisodeSetup> setups;
        std::vector<double> where;
        if (early) {
          where = std::move(started.where);
          where[0] = recv_doubles(1, 0, kTagPayload)[0];
        } else {
          setups = unpack_setups(recv_doubles(n * kSetupFields, 0, kTagPayload));
          where = recv_doubles(2 + n, 0, kTagPayload);
        }
        const auto width = static_cast<std::size_t>(where[1]);
        std::vector<std::size_t> places;
        for (std::size_t j = 0; j < n; ++j) places.push_back(static_cast<std::size_t>(where[2 + j]));
        if (!early) adopt_meshes(local.simulators(), recv_meshes(0));
        if (!model) throw std::runtime_error("MPI rollout backend: a whole rollout asked of a rank without a feed-forward model");
        std::vector<float> params(policy_size(*model));
        check(MPI_Bcast(params.data(), static_cast<int>(params.size()), MPI_FLOAT, 0, MPI_COMM_WORLD), "receive the policy");
        unpack_policy(params, *model);
        if (n_steps < 1 || width < n) throw std::runtime_error("MPI rollout backend: a rollout of no decisions or too few columns");
        std::vector<double> z(static_cast<std::size_t>(n_steps) * a * width);
        check(MPI_Bcast(z.data(), static_cast<int>(z.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD), "receive the draws");
        std::vector<Eigen::MatrixXd> normals;
        for (int k = 0; k < n_steps; ++k)
          normals.emplace_back(Eigen::Map<const Eigen::MatrixXd>(z.data() + static_cast<std::size_t>(k) * a * width,
                                                                 static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(width)));
        LendingRound lend(local, lending);
        const PackedShare p =
            pack_share(early ? core::run_started_share(local, std::move(started.obs), *model, cache, places, width,
                                                       normals, where[0])
                             : core::run_share(local, setups, *model, cache, places, width, normals, where[0]));
        started.ready = false;
        lend.done();
        // Rank 0 may still be stepping its share, on this rank's core too: wait for it asleep.
        send_without_spinning(p.floats.data(), p.floats.size(), MPI_FLOAT, 0, kTagReply, "send the rollout");
        send_without_spinning(p.doubles.data(), p.doubles.size(), MPI_DOUBLE, 0, kTagReply, "send the rollout");
        send_without_spinning(p.reasons.data(), p.reasons.size(), MPI_CHAR, 0, kTagReasons, "send the end reasons");
        send_own_meshes(local);
        lend.finish();
        lent_s += lend.lent_seconds();
        break;
      }
      case kTimes:
        send_doubles({local.settle_seconds(), local.step_seconds(), local.build_seconds(), lent_s}, 0,
                     kTagReply);
        break;
      case kCosts:
        send_doubles(local.work_since_start(), 0, kTagReply);
        break;
      case kPing: {
        recv_unsized<std::vector<double>>(0, kTagPayload, MPI_DOUBLE, "receive");
        send_doubles(std::vector<double>(static_cast<std::size_t>(std::max(0, header[1])), 0.0), 0, kTagReply);
        const std::string reasons(8, 'x');
        check(MPI_Send(reasons.data(), static_cast<int>(reasons.size()), MPI_CHAR, 0, kTagReasons, MPI_COMM_WORLD),
              "send the end reasons");
        break;
      }
      default:
        throw std::runtime_error("MPI rollout backend: unknown command " + std::to_string(header[0]) + " from rank 0");
    }
  }
}

}  // namespace codesign::cluster
