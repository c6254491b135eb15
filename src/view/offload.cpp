#include "view/offload.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <future>
#include <thread>
#include <type_traits>

#include "render/adaptive.h"
#include "render/render_scene.h"
#include "render/renderer.h"

namespace pt {

namespace {

using Clock = std::chrono::steady_clock;

/// A worker starts on a new epoch this long after it arrived: rank 0's first look at the epoch (a low-resolution
/// preview of about 10 ms, render/session.h) then has the cores to itself, which keeps the restart latency of
/// one process, and during a drag (an epoch every UI frame) no worker renders a frame that is stale at once.
constexpr double kEpochSettleSeconds = 0.02;
/// A worker sends its accumulation at most every 30 ms per million pixels (16 bytes a pixel; rank 0 replaces the
/// previous one, only the newest counts): a large image does not keep rank 0's UI thread busy receiving.
double send_interval_seconds(const Film& film) { return 0.03 * std::max(1.0, double(film.pixel_count()) * 1e-6); }

/// The messages' byte layout: the fields in order, native endianness (every rank runs the same binary).
struct Writer {
  std::vector<uint8_t> bytes;
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(uint64_t(v.size()));
    const auto* p = reinterpret_cast<const uint8_t*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
  }
  void str(const std::string& s) { vec(std::vector<char>(s.begin(), s.end())); }
};

/// Reads what Writer wrote; a short or malformed message leaves ok false (and every value read past it zero).
struct Reader {
  const std::vector<uint8_t>& bytes;
  size_t at = 0;
  bool ok = true;
  template <class T>
  void pod(T& v) {
    if (!ok || bytes.size() - at < sizeof(T)) {
      ok = false;
      v = T{};
      return;
    }
    std::memcpy(&v, bytes.data() + at, sizeof(T));
    at += sizeof(T);
  }
  template <class T>
  void vec(std::vector<T>& v) {
    uint64_t n = 0;
    pod(n);
    if (!ok || n > (bytes.size() - at) / sizeof(T)) {
      ok = false;
      v.clear();
      return;
    }
    v.resize(size_t(n));
    if (n) std::memcpy(v.data(), bytes.data() + at, size_t(n) * sizeof(T));  // an empty vector's data() may be null
    at += size_t(n) * sizeof(T);
  }
  void str(std::string& s) {
    std::vector<char> c;
    vec(c);
    s.assign(c.begin(), c.end());
  }
};

enum class Geometry : uint8_t { same, refit, rebuild };

/// The first byte of every post but the end (which is empty).
enum class PostKind : uint8_t { epoch = 1, hold = 2 };

PostKind kind_of(const std::vector<uint8_t>& post) { return PostKind(post.empty() ? 0 : post[0]); }

/// A material's and a mesh's fields in message order, for Writer (const) and Reader alike: one list, so a field
/// cannot be written and not read.
template <class Archive, class M>
void material_fields(Archive& a, M& m) {
  a.str(m.name);
  a.pod(m.type);
  a.pod(m.albedo);
  a.pod(m.ior);
  a.pod(m.emission);
}
template <class Archive, class M>
void mesh_fields(Archive& a, M& m) {
  a.str(m.name);
  a.pod(m.origin);
  a.vec(m.positions);
  a.vec(m.indices);
  a.vec(m.normals);
  a.vec(m.normal_indices);
  a.vec(m.materials);
}

/// A worker's result in message order (OffloadResult), for Writer and Reader alike.
template <class Archive, class R>
void result_fields(Archive& a, R& r) {
  a.pod(r.epoch);
  a.pod(r.rank);
  a.pod(r.width);
  a.pod(r.height);
  a.pod(r.spp);
  a.pod(r.seconds);
  a.vec(r.sum);
  a.vec(r.count);
}

std::vector<uint8_t> encode_epoch(uint64_t epoch, const RenderParams& params, const Scene& scene, Geometry geometry) {
  Writer w;
  w.pod(PostKind::epoch);
  w.pod(epoch);
  w.pod(params);
  w.pod(scene.camera.value_or(Camera{}));
  w.pod(uint8_t(scene.background.has_value()));
  w.pod(scene.background.value_or(vec3(0.0f)));
  w.pod(uint64_t(scene.materials.size()));
  for (const Material& m : scene.materials) material_fields(w, m);
  w.pod(geometry);
  if (geometry != Geometry::same) {
    w.vec(scene.spheres);
    w.vec(scene.quads);
    w.pod(uint64_t(scene.meshes.size()));
    for (const Mesh& m : scene.meshes) mesh_fields(w, m);
  }
  return std::move(w.bytes);
}

/// Applies an epoch message to `scene` and `params`; returns the geometry change, or nullopt if malformed.
std::optional<Geometry> decode_epoch(const std::vector<uint8_t>& bytes, uint64_t& epoch, RenderParams& params,
                                     Scene& scene) {
  Reader r{bytes};
  PostKind kind{};
  r.pod(kind);
  if (kind != PostKind::epoch) return std::nullopt;
  r.pod(epoch);
  r.pod(params);
  Camera cam;
  r.pod(cam);
  scene.camera = cam;
  uint8_t has_bg = 0;
  vec3 bg;
  r.pod(has_bg);
  r.pod(bg);
  scene.background = has_bg ? std::optional<vec3>(bg) : std::nullopt;
  uint64_t n = 0;
  r.pod(n);
  if (!r.ok || n > bytes.size()) return std::nullopt;
  scene.materials.assign(size_t(n), Material{});
  for (Material& m : scene.materials) material_fields(r, m);
  Geometry geometry = Geometry::same;
  r.pod(geometry);
  if (geometry != Geometry::same) {
    r.vec(scene.spheres);
    r.vec(scene.quads);
    r.pod(n);
    if (!r.ok || n > bytes.size()) return std::nullopt;
    scene.meshes.assign(size_t(n), Mesh{});
    for (Mesh& m : scene.meshes) mesh_fields(r, m);
  }
  if (!r.ok) return std::nullopt;
  return geometry;
}

}  // namespace

std::vector<uint8_t> encode_offload_hold(bool held) {
  Writer w;
  w.pod(PostKind::hold);
  w.pod(uint8_t(held));
  return std::move(w.bytes);
}

bool decode_offload_hold(const std::vector<uint8_t>& bytes, bool& held) {
  Reader r{bytes};
  PostKind kind{};
  uint8_t value = 0;
  r.pod(kind);
  r.pod(value);
  held = value != 0;
  return r.ok && kind == PostKind::hold && r.at == bytes.size() && value <= 1;
}

std::vector<uint8_t> encode_offload_result(uint64_t epoch, int rank, int spp, double seconds, const Film& film) {
  const OffloadResult res{epoch, int32_t(rank), int32_t(film.width), int32_t(film.height), int32_t(spp), seconds,
                          std::vector<float>(film.sum.begin(), film.sum.end()), film.count};
  Writer w;
  result_fields(w, res);
  return std::move(w.bytes);
}

bool decode_offload_result(const std::vector<uint8_t>& bytes, OffloadResult& out) {
  Reader r{bytes};
  result_fields(r, out);
  const size_t pixels = size_t(std::max(0, out.width)) * size_t(std::max(0, out.height));
  return r.ok && out.sum.size() == 3 * pixels && out.count.size() == pixels;
}

OffloadRoot::~OffloadRoot() {
  if (channel_) channel_->close();
}

void OffloadRoot::post_epoch(uint64_t epoch, const RenderParams& params, const Scene& scene, int builds,
                             int refits) {
  if (!channel_) return;
  Geometry g = builds != posted_builds_ ? Geometry::rebuild
               : refits != posted_refits_ ? Geometry::refit
                                          : Geometry::same;
  posted_builds_ = builds;
  posted_refits_ = refits;
  posted_epoch_ = epoch;
  channel_->post(encode_epoch(epoch, params, scene, g));
}

void OffloadRoot::set_hold(bool held) {
  if (!channel_ || held == held_) return;
  held_ = held;
  channel_->post(encode_offload_hold(held));
}

bool OffloadRoot::poll() {
  if (!channel_) return false;
  bool fresh = false;
  for (const std::vector<uint8_t>& bytes : channel_->poll_results()) {
    OffloadResult res;
    if (!decode_offload_result(bytes, res) || res.rank < 1 || res.rank > int(remote_.size())) continue;
    if (res.epoch != posted_epoch_) continue;  // stale: an edit came after it was rendered
    Remote& r = remote_[size_t(res.rank - 1)];
    r.epoch = res.epoch;
    r.width = res.width;
    r.height = res.height;
    r.spp = res.spp;
    r.seconds = res.seconds;
    r.sum = std::move(res.sum);
    r.count = std::move(res.count);
    fresh = true;
  }
  return fresh;
}

void OffloadRoot::merge(SessionFrame& out) const {
  const size_t pixels = size_t(out.width) * size_t(out.height);
  if (out.preview || out.count.size() != pixels || out.image.rgb.size() != 3 * pixels) return;
  std::vector<const Remote*> use;
  for (const Remote& r : remote_)
    if (r.epoch == out.epoch && r.width == out.width && r.height == out.height) use.push_back(&r);
  if (use.empty()) return;
  for (size_t p = 0; p < pixels; ++p) {
    double n = out.count[p];
    double s[3] = {out.image.rgb[3 * p] * n, out.image.rgb[3 * p + 1] * n, out.image.rgb[3 * p + 2] * n};
    for (const Remote* r : use) {
      n += r->count[p];
      for (int c = 0; c < 3; ++c) s[c] += r->sum[3 * p + size_t(c)];
    }
    for (int c = 0; c < 3; ++c) out.image.rgb[3 * p + size_t(c)] = n > 0 ? float(s[c] / n) : 0.0f;
  }
  for (const Remote* r : use) out.spp += r->spp;
}

bool OffloadRoot::fetch(RenderSession& session, SessionFrame& out) {
  const bool own = session.fetch(own_);
  const bool remote = poll();
  if (!own && !(remote && own_.epoch == posted_epoch_ && !own_.preview)) return false;
  if (own_.revision == 0) return false;  // nothing published yet
  out = own_;
  merge(out);
  return true;
}

std::vector<RankContribution> OffloadRoot::contributions() const {
  std::vector<RankContribution> out;
  out.push_back({0, own_.preview ? 0 : own_.spp, own_.seconds});
  for (size_t i = 0; i < remote_.size(); ++i) {
    const Remote& r = remote_[i];
    bool current = r.epoch == own_.epoch && !own_.preview;
    out.push_back({int(i) + 1, current ? r.spp : 0, current ? r.seconds : 0.0});
  }
  return out;
}

int run_offload_worker(OffloadChannel& channel, int rank, int threads) {
  Renderer renderer(threads);
  Scene scene;
  RenderParams params;
  std::shared_ptr<const RenderGeometry> geo;
  std::shared_ptr<const RenderScene> rs;
  uint64_t epoch = 0;
  Film film;
  std::vector<uint32_t> first;  // zeros: every pixel's range starts at the rank's base
  RenderCounters counters;
  bool held = false;    // rank 0's user paused: no new pass
  bool unsent = false;  // the film holds passes rank 0 has not been sent
  int frames = 0, pass_frames = 0;  // frames rendered; frames of the pass in flight
  double seconds = 0.0;
  std::atomic<bool> cancel{false};
  std::future<bool> job;
  Clock::time_point job_start, last_send, epoch_start;
  const uint32_t base = uint32_t(rank) << kRankSampleShift;
  for (;;) {
    std::vector<std::vector<uint8_t>> posts = channel.poll_posts();
    // The frame in flight reads the state an epoch (or the end) changes: stop it first. A hold lets it finish.
    const bool restart = std::any_of(posts.begin(), posts.end(),
                                     [](const std::vector<uint8_t>& m) { return kind_of(m) != PostKind::hold; });
    if (restart && job.valid()) {
      cancel = true;
      job.wait();  // the next tile at most
      job = {};
      cancel = false;
    }
    bool stop = false, fresh = false;
    Geometry change = Geometry::same;
    for (const std::vector<uint8_t>& msg : posts) {
      if (msg.empty()) {
        stop = true;
        break;
      }
      if (bool h = false; decode_offload_hold(msg, h)) {
        held = h;
        continue;
      }
      std::optional<Geometry> g = decode_epoch(msg, epoch, params, scene);
      if (!g) continue;
      fresh = true;
      change = std::max(change, *g);
    }
    if (stop) break;
    if (fresh) {
      if (change == Geometry::rebuild || !geo) geo = make_render_geometry(scene);
      else if (change == Geometry::refit) geo = refit_render_geometry(*geo, scene);
      rs = std::make_shared<RenderScene>(make_render_scene(scene, geo));
      film.reset(params.width, params.height);
      first.assign(film.pixel_count(), 0);
      counters = {};
      frames = 0;
      seconds = 0.0;
      unsent = false;
      epoch_start = Clock::now();
    }
    if (job.valid() && job.wait_for(std::chrono::seconds(0)) == std::future_status::ready && job.get()) {
      frames += pass_frames;
      seconds += std::chrono::duration<double>(Clock::now() - job_start).count();
      unsent = true;
    }
    // Between passes (the film is not being written): the first pass at once, then at most every send interval;
    // held, until the last pass has gone (a send refused while the previous one is in flight is retried here).
    if (unsent && !job.valid() &&
        (frames == 1 || held ||
         std::chrono::duration<double>(Clock::now() - last_send).count() >= send_interval_seconds(film))) {
      if (channel.send_result(encode_offload_result(epoch, rank, frames * params.spp_per_frame, seconds, film))) {
        last_send = Clock::now();
        unsent = false;
      }
    }
    const int64_t next = int64_t(frames) * params.spp_per_frame;
    const bool settled = std::chrono::duration<double>(Clock::now() - epoch_start).count() >= kEpochSettleSeconds;
    // Several frames to a pass, as rank 0's session renders them (about kInteractivePassSeconds; adaptive.h): each
    // pixel's samples of the pass are taken one after the other, the film is the same as frame by frame. The pass
    // stays inside the rank's range of sample indices.
    const int64_t room = ((int64_t(1) << kRankSampleShift) - 1 - next) / params.spp_per_frame;
    if (rs && settled && !held && !job.valid() && room > 0) {
      pass_frames = int(std::min<int64_t>(
          frames_for_pass_time(frames > 0 ? seconds / frames : 0.0, kInteractivePassSeconds), room));
      job_start = Clock::now();
      const uint32_t offset = base + uint32_t(next);
      RenderParams pass = params;
      pass.spp_per_frame = pass_frames * params.spp_per_frame;
      job = std::async(std::launch::async, [&, offset, pass] {
        return renderer.render_range(*rs, pass, film, nullptr, first.data(), offset, counters, &cancel);
      });
    }
    // Poll about every millisecond: a new epoch cancels the frame in flight within a tile.
    if (job.valid()) job.wait_for(std::chrono::milliseconds(1));
    else std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  channel.finish();
  return 0;
}

}  // namespace pt
