#include "cluster/mpi_env_pool.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include <mpi.h>

#include "cluster/rollout_messages.hpp"

namespace codesign::cluster {

namespace {

// Rank 0 -> rank r: a command header {command, flag}, then its payload (if any), all tag kCommand
// or kPayload; rank r -> rank 0: the reply (kReply) and, after a step, the end reasons (kReasons).
enum Command : int { kStop = 0, kStart = 1, kStep = 2, kTimes = 3, kPing = 4 };
constexpr int kTagCommand = 101, kTagPayload = 102, kTagReply = 103, kTagReasons = 104;

void check(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(std::string("MPI rollout backend: ") + what + ": " + std::string(text, static_cast<std::size_t>(len)));
}

void send_doubles(const std::vector<double>& v, int to, int tag) {
  check(MPI_Send(v.data(), static_cast<int>(v.size()), MPI_DOUBLE, to, tag, MPI_COMM_WORLD), "send");
}

// Waits for a posted receive without holding a core. Open MPI's blocking calls poll the shared
// memory transport in a loop, so a rank waiting through rank 0's PPO update (a fraction of a second
// per iteration) would take a core from it when the ranks share a machine. This polls for up to
// 100 µs (an answer to a step usually comes within that: docs/cluster.md), then sleeps between
// polls, 20 µs at first, doubling up to 500 µs.
void wait_without_spinning(MPI_Request& request, MPI_Status* status, const char* what) {
  int done = 0;
  const double spin_until = MPI_Wtime() + 100e-6;
  do {
    check(MPI_Test(&request, &done, status), what);
  } while (!done && MPI_Wtime() < spin_until);
  auto pause = std::chrono::microseconds(20);
  while (!done) {
    std::this_thread::sleep_for(pause);
    pause = std::min(2 * pause, std::chrono::microseconds(500));
    check(MPI_Test(&request, &done, status), what);
  }
}

void recv_into(void* data, int count, MPI_Datatype type, int from, int tag, MPI_Status* status, const char* what) {
  MPI_Request request;
  check(MPI_Irecv(data, count, type, from, tag, MPI_COMM_WORLD, &request), what);
  wait_without_spinning(request, status, what);
}

std::vector<double> recv_doubles(std::size_t n, int from, int tag) {
  std::vector<double> v(n);
  MPI_Status st;
  recv_into(v.data(), static_cast<int>(n), MPI_DOUBLE, from, tag, &st, "receive");
  int got = 0;
  MPI_Get_count(&st, MPI_DOUBLE, &got);
  if (static_cast<std::size_t>(got) != n)
    throw std::runtime_error("MPI rollout backend: a message of " + std::to_string(got) + " numbers where " +
                             std::to_string(n) + " were expected");
  return v;
}

void send_command(int to, Command c, int flag) {
  const int header[2] = {c, flag};
  check(MPI_Send(header, 2, MPI_INT, to, kTagCommand, MPI_COMM_WORLD), "send a command");
}

// The end reasons follow the step's numbers at once, so a blocking probe waits no longer than an
// exchange.
std::string recv_string(int from, int tag) {
  MPI_Status st;
  check(MPI_Probe(from, tag, MPI_COMM_WORLD, &st), "probe");
  int n = 0;
  MPI_Get_count(&st, MPI_CHAR, &n);
  std::string s(static_cast<std::size_t>(n), '\0');
  check(MPI_Recv(s.data(), n, MPI_CHAR, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "receive the end reasons");
  return s;
}

std::vector<double> columns(const Eigen::MatrixXd& m, EnvSlice s) {
  std::vector<double> v(static_cast<std::size_t>(m.rows()) * s.count);
  Eigen::Map<Eigen::MatrixXd>(v.data(), m.rows(), static_cast<Eigen::Index>(s.count)) =
      m.middleCols(static_cast<Eigen::Index>(s.first), static_cast<Eigen::Index>(s.count));
  return v;
}

}  // namespace

EnvSlice env_slice(std::size_t n_envs, int rank, int ranks) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("env_slice: rank " + std::to_string(rank) + " of " + std::to_string(ranks));
  const auto n = static_cast<std::size_t>(ranks), r = static_cast<std::size_t>(rank);
  if (n_envs < n)
    throw std::invalid_argument(std::to_string(ranks) + " MPI ranks for " + std::to_string(n_envs) +
                                " environments (designs_per_update): every rank needs at least one");
  const std::size_t base = n_envs / n, extra = n_envs % n;
  return {r * base + std::min(r, extra), base + (r < extra ? 1 : 0)};
}

MpiEnvPool::MpiEnvPool(std::unique_ptr<core::ThreadEnvPool> local, std::size_t n_envs, int ranks)
    : local_(std::move(local)), n_envs_(n_envs), ranks_(ranks) {
  for (int r = 0; r < ranks; ++r) slices_.push_back(env_slice(n_envs, r, ranks));
  if (!local_ || local_->size() != slices_[0].count)
    throw std::invalid_argument("MpiEnvPool: rank 0's pool must hold its slice of " + std::to_string(slices_[0].count) +
                                " environments");
  if (local_->threads() < 2) update_pool_ = std::make_unique<rl::ThreadPool>(2);
  result_ = rl::VecStepResult(spec().observation.dim(), n_envs);
  last_in_band_.assign(n_envs, 0);
}

MpiEnvPool::~MpiEnvPool() {
  for (int r = 1; r < ranks_; ++r) {
    const int header[2] = {kStop, 0};
    MPI_Send(header, 2, MPI_INT, r, kTagCommand, MPI_COMM_WORLD);  // no throw from a destructor
  }
}

Eigen::MatrixXd MpiEnvPool::start(const std::vector<core::EpisodeSetup>& setups) {
  if (setups.size() != n_envs_) throw std::invalid_argument("MpiEnvPool::start: one setup per environment");
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kStart, 0);
    send_doubles(pack_setups(setups, slices_[r].first, slices_[r].count), r, kTagPayload);
  }
  const std::vector<core::EpisodeSetup> mine(setups.begin(), setups.begin() + static_cast<std::ptrdiff_t>(slices_[0].count));
  const Eigen::Index d = static_cast<Eigen::Index>(spec().observation.dim());
  Eigen::MatrixXd obs(d, static_cast<Eigen::Index>(n_envs_));
  obs.leftCols(static_cast<Eigen::Index>(slices_[0].count)) = local_->start(mine);
  for (int r = 1; r < ranks_; ++r) {
    const EnvSlice s = slices_[r];
    const std::vector<double> v = recv_doubles(static_cast<std::size_t>(d) * s.count, r, kTagReply);
    obs.middleCols(static_cast<Eigen::Index>(s.first), static_cast<Eigen::Index>(s.count)) =
        Eigen::Map<const Eigen::MatrixXd>(v.data(), d, static_cast<Eigen::Index>(s.count));
  }
  return obs;
}

const rl::VecStepResult& MpiEnvPool::step(const Eigen::MatrixXd& actions, bool restart) {
  if (actions.cols() != static_cast<Eigen::Index>(n_envs_))
    throw std::invalid_argument("MpiEnvPool::step: one action column per environment");
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kStep, restart ? 1 : 0);
    send_doubles(columns(actions, slices_[r]), r, kTagPayload);
  }
  // Rank 0's slice, while the other ranks step theirs.
  const auto n0 = static_cast<Eigen::Index>(slices_[0].count);
  const rl::VecStepResult& mine = local_->step(actions.leftCols(n0), restart);
  result_.obs.leftCols(n0) = mine.obs;
  result_.rewards.head(n0) = mine.rewards;
  for (std::size_t i = 0; i < slices_[0].count; ++i) {
    result_.terminated[i] = mine.terminated[i];
    result_.truncated[i] = mine.truncated[i];
    result_.terminal_obs[i] = mine.terminal_obs[i];
    result_.reasons[i] = mine.reasons[i];
    if (mine.done(i)) last_in_band_[i] = local_->last_in_band(i);
  }
  const std::size_t d = spec().observation.dim();
  for (int r = 1; r < ranks_; ++r) {
    const EnvSlice s = slices_[r];
    const std::vector<double> v = recv_doubles(s.count * (kStepFields + 2 * d), r, kTagReply);
    const std::vector<std::string> reasons = split_reasons(recv_string(r, kTagReasons), s.count);
    unpack_step(v, d, s.first, result_, last_in_band_);
    for (std::size_t k = 0; k < s.count; ++k) result_.reasons[s.first + k] = reasons[k];
  }
  return result_;
}

// The settle and step CPU seconds of ranks 1.. (one query each).
std::array<double, 2> MpiEnvPool::remote_seconds() const {
  std::array<double, 2> sum{0.0, 0.0};
  for (int r = 1; r < ranks_; ++r) {
    send_command(r, kTimes, 0);
    const std::vector<double> v = recv_doubles(2, r, kTagReply);
    sum[0] += v[0];
    sum[1] += v[1];
  }
  return sum;
}

double MpiEnvPool::settle_seconds() const { return local_->settle_seconds() + remote_seconds()[0]; }

double MpiEnvPool::step_seconds() const { return local_->step_seconds() + remote_seconds()[1]; }

void MpiEnvPool::set_step_observer(std::size_t i, StepObserver observer, int every) {
  if (i >= slices_[0].count)
    throw std::invalid_argument("MpiEnvPool: environment " + std::to_string(i) +
                                " is stepped on another rank; live telemetry follows rank 0's environments only");
  local_->set_step_observer(i, std::move(observer), every);
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

void serve_env_pool(core::ThreadEnvPool& local) {
  const std::size_t n = local.size(), a = local.spec().action.dim();
  for (;;) {
    int header[2] = {0, 0};
    recv_into(header, 2, MPI_INT, 0, kTagCommand, MPI_STATUS_IGNORE, "receive a command");
    switch (header[0]) {
      case kStop:
        return;
      case kStart: {
        const std::vector<core::EpisodeSetup> setups = unpack_setups(recv_doubles(n * kSetupFields, 0, kTagPayload));
        const Eigen::MatrixXd obs = local.start(setups);
        send_doubles(std::vector<double>(obs.data(), obs.data() + obs.size()), 0, kTagReply);
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
      case kTimes:
        send_doubles({local.settle_seconds(), local.step_seconds()}, 0, kTagReply);
        break;
      case kPing: {
        MPI_Status st;
        check(MPI_Probe(0, kTagPayload, MPI_COMM_WORLD, &st), "probe");
        int got = 0;
        MPI_Get_count(&st, MPI_DOUBLE, &got);
        recv_doubles(static_cast<std::size_t>(got), 0, kTagPayload);
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
