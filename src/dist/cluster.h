#pragma once
/// A group of processes that render one image together by sample-range sharding (OSPRay's MPI module does the same
/// for its distributed framebuffer). Every pixel sample is seeded from (seed, pixel, sample index) alone, so rank r
/// of K renders the global frames r, r + K, r + 2K, ... (their sample indices) and no sample is rendered twice;
/// rank 0 sums the films and writes every output.
///
/// This header has no MPI in it: one process is the Solo cluster (what ptview is without mpirun), and the MPI
/// implementation lives in src/dist/mpi/ (built when the CMake option PTVIEW_MPI is on).
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "render/film.h"
#include "render/stats.h"
#include "render/stats_json.h"  // RankWork

namespace pt {

/// The viewer offload's messages (OSPRay's mpiOffload, for a progressive viewer; src/view/offload.h gives them
/// meaning): rank 0 posts every epoch to all other ranks, and they send their accumulations back. Nothing here
/// blocks, except the closing handshake: every call is made by the main thread (rank 0's UI thread), which polls.
class OffloadChannel {
 public:
  virtual ~OffloadChannel() = default;
  /// Rank 0: sends `message` to every other rank, in order (an empty message ends the workers: see close).
  virtual void post(std::vector<uint8_t> message) = 0;
  /// Rank 0: the accumulations that have arrived since the last call (each whole, as sent).
  virtual std::vector<std::vector<uint8_t>> poll_results() = 0;
  /// Rank 0: posts the end, then receives (and drops) results until every other rank has said goodbye, so that
  /// no message is left in flight when MPI finalizes. Blocks for at most the other ranks' current frame.
  virtual void close() = 0;
  /// Other ranks: the posts that arrived since the last call, oldest first (an empty one: stop).
  virtual std::vector<std::vector<uint8_t>> poll_posts() = 0;
  /// Other ranks: sends an accumulation to rank 0 unless the previous one is still in flight (then false: the
  /// next, more complete, one replaces it).
  virtual bool send_result(std::vector<uint8_t> message) = 0;
  /// Other ranks, after the empty post: waits for its sends and says goodbye.
  virtual void finish() = 0;
};

class Cluster {
 public:
  virtual ~Cluster() = default;
  virtual int rank() const { return 0; }
  virtual int ranks() const { return 1; }
  bool root() const { return rank() == 0; }
  /// Worker threads for `--threads 0`: all cores for one process, the cores shared among the ranks on this node
  /// under MPI (ranks on one machine would otherwise oversubscribe it).
  virtual int default_threads() const { return 0; }

  /// Collective. True on every rank if `mine` is true on any rank (the time limit: ranks stop in the same round).
  virtual bool any(bool mine) { return mine; }
  /// Collective. Empty when no rank has an error; otherwise the error of the lowest failing rank, named by rank and
  /// host when it is not rank 0's own, on every rank.
  virtual std::string first_error(const std::string& mine) { return mine; }
  /// Collective. On rank 0, `total` becomes the sum of every rank's `local` (every Film::for_each_buffer
  /// buffer), added in a fixed order; other ranks leave `total` untouched.
  virtual void sum_films(Film& local, Film& total) { total = local; }
  /// Collective. Every rank gets rank 0's `data` (the same size on every rank).
  virtual void broadcast(std::span<uint8_t> data) { (void)data; }
  /// Collective. Rank 0 gets the sum of the counters of every rank.
  virtual RenderCounters sum_counters(const RenderCounters& mine) { return mine; }
  /// Collective. Rank 0 gets every rank's work, in rank order.
  virtual std::vector<RankWork> gather_work(const RankWork& mine) { return {mine}; }
  /// The viewer offload's channel; null for one process.
  virtual std::unique_ptr<OffloadChannel> offload_channel() { return nullptr; }
  /// Milliseconds this process spent in MPI calls (including waiting for slower ranks).
  virtual double comm_ms() const { return 0.0; }
};

/// Prints an agreed error (from first_error) as one line on rank 0 and returns the process exit code: 2 on rank 0,
/// 0 on the others, so that the launcher (which stops every rank when one exits non-zero) cannot cut rank 0 short
/// while it reports; the job's exit code is rank 0's.
int report_error(const Cluster& cluster, const std::string& error);

/// The cluster this process belongs to: MPI when the binary was built with PTVIEW_MPI and started by an MPI
/// launcher (mpirun, mpiexec, srun), otherwise Solo, with no MPI call at all. Destroying it finalizes MPI.
std::unique_ptr<Cluster> join_cluster();

/// The global frame rank `rank` of `ranks` renders in round `round` (frame = sample range
/// [frame * spp_per_frame, (frame + 1) * spp_per_frame) of every pixel).
inline int64_t shard_frame(int64_t round, int rank, int ranks) { return round * ranks + rank; }
/// Frames rendered by all ranks together after `rounds` rounds (0 frames_total: no frame limit).
inline int64_t frames_after_rounds(int64_t rounds, int ranks, int64_t frames_total) {
  int64_t f = rounds * ranks;
  return frames_total > 0 && f > frames_total ? frames_total : f;
}

}  // namespace pt
