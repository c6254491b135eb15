#include "raycast_embree.h"

#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#ifdef PTVIEW_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace bench {

namespace {

/// A field of /proc/self/status in bytes ("VmRSS:   1234 kB"), or -1.
double proc_status_bytes(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::char_traits<char>::length(key);
  while (std::getline(in, line))
    if (line.compare(0, n, key) == 0 && line.size() > n && line[n] == ':')
      return std::stod(line.substr(n + 1)) * 1024.0;
  return -1.0;
}

}  // namespace

PeakRssProbe::PeakRssProbe() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5" << std::flush;
  if (clear) rss_before_ = proc_status_bytes("VmRSS");
}

double PeakRssProbe::growth() const {
  if (rss_before_ < 0.0) return -1.0;
  double hwm = proc_status_bytes("VmHWM");
  return hwm < 0.0 ? -1.0 : std::max(0.0, hwm - rss_before_);
}

#ifdef PTVIEW_HAVE_EMBREE

bool embree_available() { return true; }
std::string embree_version() { return RTC_VERSION_STRING; }

namespace {

/// Bytes the device holds now and at most since the last reset; Embree calls this from its build threads.
struct MemoryMonitor {
  std::atomic<long long> current{0}, peak{0};
  static bool callback(void* user, ssize_t bytes, bool /*post*/) {
    auto* m = static_cast<MemoryMonitor*>(user);
    long long now = m->current.fetch_add(bytes) + bytes;
    long long p = m->peak.load();
    while (now > p && !m->peak.compare_exchange_weak(p, now)) {
    }
    return true;  // never refuse an allocation
  }
};

void report_error(void*, RTCError code, const char* str) {
  std::fprintf(stderr, "embree error %d: %s\n", int(code), str ? str : "");
}

}  // namespace

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  MemoryMonitor monitor;
  std::vector<pt::vec3> vertices;  ///< a padded copy: Embree reads the last vertex with a 16-byte load
  std::vector<uint32_t> indices;   ///< 0, 1, 2, 3, ...: the input is a triangle soup
};

EmbreeScene::EmbreeScene(std::span<const pt::vec3> triangle_vertices, EmbreeQuality quality, int device_threads)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  const std::string config = device_threads > 0 ? "threads=" + std::to_string(device_threads) : "";
  m.device = rtcNewDevice(config.c_str());
  rtcSetDeviceErrorFunction(m.device, report_error, nullptr);
  rtcSetDeviceMemoryMonitorFunction(m.device, MemoryMonitor::callback, &m.monitor);

  const size_t tris = triangle_vertices.size() / 3;
  m.vertices.assign(triangle_vertices.begin(), triangle_vertices.begin() + 3 * tris);
  m.vertices.push_back(pt::vec3(0.0f));
  m.indices.resize(3 * tris);
  for (size_t i = 0; i < m.indices.size(); ++i) m.indices[i] = uint32_t(i);

  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(m.scene, quality == EmbreeQuality::high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.vertices.data(), 0,
                             sizeof(pt::vec3), 3 * tris);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(), 0,
                             3 * sizeof(uint32_t), tris);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(m.scene, geom);
  rtcReleaseGeometry(geom);

  // Only the commit is timed: it is where Embree builds the BVH.
  const long long before = m.monitor.current.load();
  m.monitor.peak.store(before);
  PeakRssProbe rss;
  auto start = std::chrono::steady_clock::now();
  rtcCommitScene(m.scene);
  build_.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  build_.rss_peak = rss.growth();
  build_.net_bytes = double(m.monitor.current.load() - before);
  build_.monitor_peak = double(m.monitor.peak.load() - before);
}

EmbreeScene::~EmbreeScene() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

bool EmbreeScene::intersect(const pt::Ray& ray, float& t, uint32_t& prim) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.org.x, rh.ray.org_y = ray.org.y, rh.ray.org_z = ray.org.z;
  rh.ray.dir_x = ray.dir.x, rh.ray.dir_y = ray.dir.y, rh.ray.dir_z = ray.dir.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = ray.tmax;
  rh.ray.time = 0.0f;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  t = rh.ray.tfar;
  prim = rh.hit.primID;
  return true;
}

bool EmbreeScene::occluded(const pt::Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  r.org_x = ray.org.x, r.org_y = ray.org.y, r.org_z = ray.org.z;
  r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
  r.tnear = 0.0f;
  r.tfar = ray.tmax;
  r.time = 0.0f;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(impl_->scene, &context, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to -inf when the ray is blocked
}

#else  // no Embree: the benchmark runs our side only

bool embree_available() { return false; }
std::string embree_version() { return ""; }

struct EmbreeScene::Impl {};
EmbreeScene::EmbreeScene(std::span<const pt::vec3>, EmbreeQuality, int) {}
EmbreeScene::~EmbreeScene() = default;
bool EmbreeScene::intersect(const pt::Ray&, float&, uint32_t&) const { return false; }
bool EmbreeScene::occluded(const pt::Ray&) const { return false; }

#endif

}  // namespace bench
