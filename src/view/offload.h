#pragma once
/// The viewer offload (OSPRay's mpiOffload, made progressive): `mpirun -np K ptview SCENE` opens the window on rank 0;
/// ranks 1..K-1 render more samples of whatever rank 0 shows.
///
/// Every restart of rank 0's session is an epoch. Rank 0 posts the state it restarts with (render parameters,
/// camera, background and materials, and the geometry whenever it was rebuilt or refitted) as a snapshot, never an
/// edit to replay, so a worker cannot drift from rank 0 whatever input made the change. A worker renders sample
/// ranges of the newest epoch (rank r: the sample indices r * 2^24, r * 2^24 + 1, ... of every pixel, disjoint
/// from rank 0's 0, 1, ... and from every other rank's) and sends its accumulation (per-pixel sums and counts) to
/// rank 0 every few frames. Rank 0 receives on its UI thread without ever waiting (OffloadChannel, src/dist),
/// drops results of any epoch but the newest on arrival, and shows the merged mean: its own session's samples
/// plus every rank's latest accumulation of the same epoch.
///
/// The user's pause holds every rank: rank 0 posts it (a hold message, apart from the epochs, since a pause is no
/// restart), and a worker finishes the pass in flight, sends it, and starts no other until the hold is lifted; its
/// samples stay in the merged image, and resuming continues its sample range where it stopped.
///
/// Not distributed (rank 0 alone): the low-resolution first look of an epoch, adaptive sampling's stopped pixels,
/// the target spp, and the B side of an A/B compare.
#include <cstdint>
#include <memory>
#include <vector>

#include "dist/cluster.h"
#include "render/session.h"
#include "scene/scene.h"

namespace pt {

/// Sample indices of rank r start at r * 2^24: no rank reaches another's range before 16 million samples per pixel.
inline constexpr int kRankSampleShift = 24;

/// One rank's latest contribution to the current epoch, for the Stats panel and the stats JSON.
struct RankContribution {
  int rank = 0;
  int spp = 0;
  double seconds = 0.0;  ///< its render time in this epoch
  double spp_per_s() const { return seconds > 0 ? spp / seconds : 0.0; }
};

/// Rank 0's side. Destroying it ends the workers (OffloadChannel::close).
class OffloadRoot {
 public:
  explicit OffloadRoot(std::unique_ptr<OffloadChannel> channel) : channel_(std::move(channel)) {}
  ~OffloadRoot();
  OffloadRoot(const OffloadRoot&) = delete;
  OffloadRoot& operator=(const OffloadRoot&) = delete;

  /// Posts epoch `epoch` of rank 0's session. The geometry travels too when `builds` (full BVH builds so far) or
  /// `refits` (refits so far) changed since the last post: rebuilt by the workers, or refitted if only `refits` did.
  void post_epoch(uint64_t epoch, const RenderParams& params, const Scene& scene, int builds, int refits);
  /// Holds (the user paused) or releases the workers; posts only a change.
  void set_hold(bool held);
  /// Fetches rank 0's newest frame from `session` and the other ranks' results; when either is new, `out` becomes
  /// the merged frame (spp: all ranks' samples per pixel). Never waits.
  bool fetch(RenderSession& session, SessionFrame& out);
  /// Every rank's contribution to the shown epoch, rank 0 first (rank 0 from the last fetched frame).
  std::vector<RankContribution> contributions() const;
  int ranks() const { return int(remote_.size()) + 1; }
  void set_ranks(int ranks) { remote_.assign(size_t(std::max(0, ranks - 1)), Remote{}); }

 private:
  struct Remote {
    uint64_t epoch = 0;
    int width = 0, height = 0;
    int spp = 0;
    double seconds = 0.0;
    std::vector<float> sum;  ///< 3 per pixel
    std::vector<uint32_t> count;
  };
  bool poll();
  void merge(SessionFrame& out) const;

  std::unique_ptr<OffloadChannel> channel_;
  uint64_t posted_epoch_ = 0;
  bool held_ = false;
  int posted_builds_ = -1, posted_refits_ = -1;
  SessionFrame own_;
  std::vector<Remote> remote_;  ///< ranks 1..K-1
};

/// Rank 0's posts: an epoch (encode_epoch, in offload.cpp) or a hold. decode_offload_hold is false for any other
/// message.
std::vector<uint8_t> encode_offload_hold(bool held);
bool decode_offload_hold(const std::vector<uint8_t>& bytes, bool& held);

/// A worker's message to rank 0: its accumulation `film` of epoch `epoch` (spp samples per pixel, in `seconds`).
std::vector<uint8_t> encode_offload_result(uint64_t epoch, int rank, int spp, double seconds, const Film& film);

/// That message read back: the film's per-pixel sums (3 a pixel, as float) and finite-sample counts.
struct OffloadResult {
  uint64_t epoch = 0;
  int32_t rank = 0, width = 0, height = 0, spp = 0;
  double seconds = 0.0;
  std::vector<float> sum;
  std::vector<uint32_t> count;
};
/// False for a malformed message.
bool decode_offload_result(const std::vector<uint8_t>& bytes, OffloadResult& out);

/// Ranks 1..K-1 of a viewer run: renders the epochs rank 0 posts until it posts the end; returns the exit code.
/// `threads` worker threads (0: all cores).
int run_offload_worker(OffloadChannel& channel, int rank, int threads);

}  // namespace pt
