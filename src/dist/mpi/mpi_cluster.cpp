/// The MPI cluster: the only file that includes mpi.h. Every call is collective on MPI_COMM_WORLD and made by the
/// main thread only (MPI_THREAD_FUNNELED); the worker pools never touch MPI.
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <exception>
#include <memory>
#include <thread>
#include <type_traits>
#include <variant>

#include "dist/cluster.h"

namespace pt {

namespace {

template <class T>
MPI_Datatype mpi_type() {
  if constexpr (std::is_same_v<T, double>) return MPI_DOUBLE;
  else if constexpr (std::is_same_v<T, float>) return MPI_FLOAT;
  else if constexpr (std::is_same_v<T, uint32_t>) return MPI_UINT32_T;
  else if constexpr (std::is_same_v<T, uint64_t>) return MPI_UINT64_T;
  else static_assert(sizeof(T) == 0, "add this Film buffer's element type to mpi_type");
}

/// The Film buffers as a list, so that `local` and `total` can be walked side by side.
using SumBuffer = std::variant<std::span<double>, std::span<float>, std::span<uint32_t>, std::span<uint64_t>>;
std::vector<SumBuffer> sum_buffers(Film& film) {
  std::vector<SumBuffer> out;
  film.for_each_buffer([&](auto span) { out.emplace_back(span); });
  return out;
}

/// Rank 0 is told by the launcher to stop when another rank died: say so in one line (async-signal-safe), no
/// output has been written (outputs are written only after the last reduction, atomically).
extern "C" void on_terminate(int sig) {
  static const char msg[] = "ptview: error: stopped by the MPI launcher (a rank failed or died); no output written\n";
  ssize_t ignored = ::write(STDERR_FILENO, msg, sizeof msg - 1);
  (void)ignored;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

/// Tags of the offload messages (MPI_COMM_WORLD; the headless collectives use tag 0 and never run at the same time).
constexpr int kTagPost = 11, kTagResult = 12, kTagBye = 13;

/// Every message is sent with MPI_Isend and its buffer kept until MPI_Test says it went; results are matched with
/// MPI_Improbe and received with MPI_Imrecv into a buffer of their size, so rank 0 never waits for one.
class MpiOffloadChannel final : public OffloadChannel {
 public:
  explicit MpiOffloadChannel(int size) : size_(size) {}
  ~MpiOffloadChannel() override {
    for (Pending& p : sends_) MPI_Wait(&p.request, MPI_STATUS_IGNORE);
    for (Pending& p : recvs_) MPI_Wait(&p.request, MPI_STATUS_IGNORE);
  }

  void post(std::vector<uint8_t> message) override {
    complete_sends();
    for (int r = 1; r < size_; ++r) {
      auto buf = std::make_shared<std::vector<uint8_t>>(message);
      sends_.push_back({MPI_REQUEST_NULL, buf});
      MPI_Isend(buf->data(), int(buf->size()), MPI_BYTE, r, kTagPost, MPI_COMM_WORLD, &sends_.back().request);
    }
  }

  std::vector<std::vector<uint8_t>> poll_results() override { return receive(kTagResult); }

  void close() override {
    post({});
    int byes = 0;
    while (byes < size_ - 1) {
      receive(kTagResult);  // dropped
      int flag = 0;
      MPI_Status st;
      MPI_Iprobe(MPI_ANY_SOURCE, kTagBye, MPI_COMM_WORLD, &flag, &st);
      if (flag) {
        MPI_Recv(nullptr, 0, MPI_BYTE, st.MPI_SOURCE, kTagBye, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        ++byes;
      } else {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    }
    // Each worker completed its last send before saying goodbye: match what is left and complete every receive.
    receive(kTagResult);
    for (Pending& p : recvs_) MPI_Wait(&p.request, MPI_STATUS_IGNORE);
    recvs_.clear();
    for (Pending& p : sends_) MPI_Wait(&p.request, MPI_STATUS_IGNORE);
    sends_.clear();
  }

  std::vector<std::vector<uint8_t>> poll_posts() override {
    complete_sends();
    std::vector<std::vector<uint8_t>> out;
    for (;;) {  // posts are small: a blocking receive of a matched one does not wait
      int flag = 0;
      MPI_Status st;
      MPI_Iprobe(0, kTagPost, MPI_COMM_WORLD, &flag, &st);
      if (!flag) break;
      int n = 0;
      MPI_Get_count(&st, MPI_BYTE, &n);
      out.emplace_back(size_t(n));
      MPI_Recv(out.back().data(), n, MPI_BYTE, 0, kTagPost, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    return out;
  }

  bool send_result(std::vector<uint8_t> message) override {
    complete_sends();
    if (!sends_.empty()) return false;
    auto buf = std::make_shared<std::vector<uint8_t>>(std::move(message));
    sends_.push_back({MPI_REQUEST_NULL, buf});
    MPI_Isend(buf->data(), int(buf->size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD, &sends_.back().request);
    return true;
  }

  void finish() override {
    for (Pending& p : sends_) MPI_Wait(&p.request, MPI_STATUS_IGNORE);
    sends_.clear();
    MPI_Send(nullptr, 0, MPI_BYTE, 0, kTagBye, MPI_COMM_WORLD);
  }

 private:
  struct Pending {
    MPI_Request request;
    std::shared_ptr<std::vector<uint8_t>> buffer;
  };

  void complete_sends() {
    std::erase_if(sends_, [](Pending& p) {
      int done = 0;
      MPI_Test(&p.request, &done, MPI_STATUS_IGNORE);
      return done != 0;
    });
  }

  /// Starts receiving every matched message of `tag`, tests those in flight, returns the completed ones in the
  /// order they were matched.
  std::vector<std::vector<uint8_t>> receive(int tag) {
    for (;;) {
      int flag = 0;
      MPI_Message msg;
      MPI_Status st;
      MPI_Improbe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &flag, &msg, &st);
      if (!flag) break;
      int n = 0;
      MPI_Get_count(&st, MPI_BYTE, &n);
      recvs_.push_back({MPI_REQUEST_NULL, std::make_shared<std::vector<uint8_t>>(size_t(n))});
      MPI_Imrecv(recvs_.back().buffer->data(), n, MPI_BYTE, &msg, &recvs_.back().request);
    }
    std::vector<std::vector<uint8_t>> out;
    while (!recvs_.empty()) {  // in order: a later message never overtakes an earlier one of the same rank
      int done = 0;
      MPI_Test(&recvs_.front().request, &done, MPI_STATUS_IGNORE);
      if (!done) break;
      out.push_back(std::move(*recvs_.front().buffer));
      recvs_.erase(recvs_.begin());
    }
    return out;
  }

  int size_;
  std::vector<Pending> sends_, recvs_;
};

class MpiCluster final : public Cluster {
 public:
  MpiCluster() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &node_ranks_);
    MPI_Comm_free(&node);
    char host[MPI_MAX_PROCESSOR_NAME] = "";
    int len = 0;
    MPI_Get_processor_name(host, &len);
    host_.assign(host, size_t(len));
    if (rank_ == 0 && size_ > 1) std::signal(SIGTERM, on_terminate);
  }
  /// Leaving by an exception (out of memory on one rank) while the others wait in a collective: MPI_Finalize would
  /// wait for them forever, so abort the whole job instead.
  ~MpiCluster() override {
    if (std::uncaught_exceptions() > 0) MPI_Abort(MPI_COMM_WORLD, 2);
    if (rank_ == 0 && size_ > 1) std::signal(SIGTERM, SIG_DFL);  // the run is over: nothing left to report
    MPI_Finalize();
  }

  int rank() const override { return rank_; }
  int ranks() const override { return size_; }
  int default_threads() const override {
    int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    return std::max(1, cores / std::max(1, node_ranks_));
  }
  double comm_ms() const override { return comm_ms_; }
  std::unique_ptr<OffloadChannel> offload_channel() override {
    return size_ > 1 ? std::make_unique<MpiOffloadChannel>(size_) : nullptr;
  }

  bool any(bool mine) override {
    Timer t(comm_ms_);
    int in = mine ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return out != 0;
  }

  std::string first_error(const std::string& mine) override {
    Timer t(comm_ms_);
    int in = mine.empty() ? size_ : rank_, failed = size_;
    MPI_Allreduce(&in, &failed, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (failed == size_) return {};
    // The failing rank sends its message and host to every rank (the message size first).
    std::string text = mine;
    if (failed != 0) text = "rank " + std::to_string(failed) + " on " + host_ + ": " + mine;
    int n = int(text.size());
    MPI_Bcast(&n, 1, MPI_INT, failed, MPI_COMM_WORLD);
    text.resize(size_t(n));
    MPI_Bcast(text.data(), n, MPI_CHAR, failed, MPI_COMM_WORLD);
    return text;
  }

  /// A binomial tree with a fixed pairing: in step s = 1, 2, 4, ... rank r (a multiple of 2s) adds what rank r + s
  /// holds. The parenthesization depends only on K, so a K-rank image is bit-reproducible, and rank 0 receives
  /// log2(K) films instead of K - 1. Buffers travel in chunks of 4 MiB: memory stays small at any resolution.
  void sum_films(Film& local, Film& total) override {
    Timer t(comm_ms_);
    if (rank_ == 0) total.reset(local.width, local.height);
    std::vector<SumBuffer> mine = sum_buffers(local), out = sum_buffers(total);
    for (size_t b = 0; b < mine.size(); ++b) {
      std::visit(
          [&](auto src) {
            using T = typename decltype(src)::element_type;
            tree_sum<T>(src, rank_ == 0 ? std::get<std::span<T>>(out[b]) : std::span<T>());
          },
          mine[b]);
    }
  }

  void broadcast(std::span<uint8_t> data) override {
    Timer t(comm_ms_);
    const size_t chunk = size_t(1) << 30;  // MPI counts are int
    for (size_t off = 0; off < data.size(); off += chunk)
      MPI_Bcast(data.data() + off, int(std::min(chunk, data.size() - off)), MPI_UINT8_T, 0, MPI_COMM_WORLD);
  }

  RenderCounters sum_counters(const RenderCounters& mine) override {
    static_assert(sizeof(RenderCounters) % sizeof(uint64_t) == 0 && std::is_trivially_copyable_v<RenderCounters>,
                  "RenderCounters is reduced as an array of uint64_t");
    Timer t(comm_ms_);
    constexpr int n = int(sizeof(RenderCounters) / sizeof(uint64_t));
    uint64_t in[n], out[n] = {};
    std::memcpy(in, &mine, sizeof in);
    MPI_Reduce(in, out, n, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    RenderCounters total;
    std::memcpy(&total, out, sizeof out);
    return rank_ == 0 ? total : mine;
  }

  std::vector<RankWork> gather_work(const RankWork& mine) override {
    Timer t(comm_ms_);
    double in[2] = {double(mine.spp), mine.seconds};
    std::vector<double> all(rank_ == 0 ? 2 * size_t(size_) : 0);
    MPI_Gather(in, 2, MPI_DOUBLE, all.data(), 2, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    std::vector<RankWork> out;
    for (size_t i = 0; i + 1 < all.size(); i += 2) out.push_back({int(all[i]), all[i + 1]});
    return out;
  }

 private:
  struct Timer {
    double& ms;
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    explicit Timer(double& m) : ms(m) {}
    ~Timer() { ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(); }
  };

  template <class T>
  void tree_sum(std::span<T> mine, std::span<T> out) {
    const size_t chunk = (size_t(4) << 20) / sizeof(T);
    std::vector<T> acc, in;
    for (size_t off = 0; off < mine.size(); off += chunk) {
      const size_t m = std::min(chunk, mine.size() - off);
      acc.assign(mine.begin() + ptrdiff_t(off), mine.begin() + ptrdiff_t(off + m));
      for (int step = 1; step < size_; step *= 2) {
        if (rank_ % (2 * step) == step) {
          MPI_Send(acc.data(), int(m), mpi_type<T>(), rank_ - step, 0, MPI_COMM_WORLD);
          break;
        }
        if (rank_ % (2 * step) == 0 && rank_ + step < size_) {
          in.resize(m);
          MPI_Recv(in.data(), int(m), mpi_type<T>(), rank_ + step, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
          for (size_t i = 0; i < m; ++i) acc[i] += in[i];
        }
      }
      if (rank_ == 0) std::copy(acc.begin(), acc.end(), out.begin() + ptrdiff_t(off));
    }
  }

  int rank_ = 0, size_ = 1, node_ranks_ = 1;
  std::string host_;
  double comm_ms_ = 0.0;
};

}  // namespace

std::unique_ptr<Cluster> join_mpi_cluster() { return std::make_unique<MpiCluster>(); }

}  // namespace pt
