#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "ray_buffer.hpp"

namespace rtmini::bench {

struct EmbreePeer::State {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

using Clock = std::chrono::steady_clock;

EmbreePeer::EmbreePeer(const std::vector<Triangle>& tris) : state_(new State), tris_(tris) {
  state_->device = rtcNewDevice(nullptr);
  if (!state_->device) throw std::runtime_error("embree: rtcNewDevice failed");
}

EmbreePeer::~EmbreePeer() {
  if (state_->scene) rtcReleaseScene(state_->scene);
  rtcReleaseDevice(state_->device);
}

std::string EmbreePeer::version() const {
  return std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
         std::to_string(RTC_VERSION_PATCH);
}

double EmbreePeer::build() {
  if (state_->scene) rtcReleaseScene(state_->scene);
  const auto t0 = Clock::now();
  RTCScene scene = rtcNewScene(state_->device);
  RTCGeometry geom = rtcNewGeometry(state_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t n = tris_.size();
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p[3] = {tris_[i].a, tris_[i].b, tris_[i].c};
    for (int k = 0; k < 3; ++k) {
      v[9 * i + 3 * k + 0] = static_cast<float>(p[k].x);
      v[9 * i + 3 * k + 1] = static_cast<float>(p[k].y);
      v[9 * i + 3 * k + 2] = static_cast<float>(p[k].z);
      idx[3 * i + k] = static_cast<unsigned>(3 * i + k);
    }
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  state_->scene = scene;
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Packets of 8 consecutive rays through rtcIntersect8 / rtcOccluded8 (--peer-packets), as
// rtmini's packets take them.
static void trace_packets8(RTCScene scene, const std::vector<Ray>& rays, bool any_hit,
                           std::vector<int>& result) {
  const long long nr = static_cast<long long>(rays.size());
#pragma omp parallel for schedule(dynamic, 512)
  for (long long p = 0; p < (nr + 7) / 8; ++p) {
    const long long first = 8 * p;
    const int count = static_cast<int>(std::min(8LL, nr - first));
    alignas(32) int valid[8];
    RTCRayHit8 rh;
    for (int k = 0; k < 8; ++k) {
      valid[k] = k < count ? -1 : 0;
      const Ray& r = rays[first + (k < count ? k : 0)];
      rh.ray.org_x[k] = float(r.org.x);
      rh.ray.org_y[k] = float(r.org.y);
      rh.ray.org_z[k] = float(r.org.z);
      rh.ray.dir_x[k] = float(r.dir.x);
      rh.ray.dir_y[k] = float(r.dir.y);
      rh.ray.dir_z[k] = float(r.dir.z);
      rh.ray.tnear[k] = float(r.tmin);
      rh.ray.tfar[k] = float(r.tmax);
      rh.ray.mask[k] = ~0u;
      rh.ray.flags[k] = 0;
      rh.ray.time[k] = 0.f;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (any_hit) {
      rtcOccluded8(valid, scene, &ctx, &rh.ray);
      for (int k = 0; k < count; ++k)
        result[first + k] = rh.ray.tfar[k] == -std::numeric_limits<float>::infinity() ? 1 : 0;
    } else {
      rtcIntersect8(valid, scene, &ctx, &rh);
      for (int k = 0; k < count; ++k)
        result[first + k] =
            rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? -1 : static_cast<int>(rh.hit.primID[k]);
    }
  }
}

double EmbreePeer::trace(const std::vector<Ray>& rays, bool any_hit, std::vector<int>& result,
                         bool packets) const {
  if (!state_->scene) throw std::runtime_error("embree: trace before build");
  if (packets) {
    result.assign(rays.size(), 0);
    const auto s = Clock::now();
    trace_packets8(state_->scene, rays, any_hit, result);
    return std::chrono::duration<double>(Clock::now() - s).count();
  }
  RTCScene scene = state_->scene;
  const long long nr = static_cast<long long>(rays.size());
  result.assign(rays.size(), 0);
  const auto s = Clock::now();
#pragma omp parallel for schedule(dynamic, 4096)
  for (long long i = 0; i < nr; ++i) {
    const Ray& r = rays[i];
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = float(r.org.x);
    rh.ray.org_y = float(r.org.y);
    rh.ray.org_z = float(r.org.z);
    rh.ray.dir_x = float(r.dir.x);
    rh.ray.dir_y = float(r.dir.y);
    rh.ray.dir_z = float(r.dir.z);
    rh.ray.tnear = float(r.tmin);
    rh.ray.tfar = float(r.tmax);
    rh.ray.mask = ~0u;
    rh.ray.flags = 0;
    rh.ray.time = 0.f;
    if (any_hit) {
      rtcOccluded1(scene, &ctx, &rh.ray);
      // Embree marks an occluded ray with tfar = -inf; an empty segment (tmax < 0) is unoccluded.
      result[i] = rh.ray.tfar == -std::numeric_limits<float>::infinity() ? 1 : 0;
    } else {
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      result[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : static_cast<int>(rh.hit.primID);
    }
  }
  return std::chrono::duration<double>(Clock::now() - s).count();
}

}  // namespace rtmini::bench
