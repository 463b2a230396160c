#include <embree3/rtcore.h>

#include <chrono>
#include <limits>
#include <stdexcept>

#include "ray_buffer.hpp"

namespace rtmini::bench {

PeerResult trace_with_embree(const std::vector<Triangle>& tris, const std::vector<Ray>& rays,
                             bool any_hit, int repeats) {
  using Clock = std::chrono::steady_clock;
  PeerResult out;
  out.version = std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
                std::to_string(RTC_VERSION_PATCH);
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error("embree: rtcNewDevice failed");
  const auto t0 = Clock::now();
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t n = tris.size();
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p[3] = {tris[i].a, tris[i].b, tris[i].c};
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
  out.build_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  const long long nr = static_cast<long long>(rays.size());
  out.result.assign(rays.size(), 0);
  double best = 1e300;
  for (int rep = 0; rep < repeats; ++rep) {
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
        out.result[i] = rh.ray.tfar == -std::numeric_limits<float>::infinity() ? 1 : 0;
      } else {
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        out.result[i] =
            rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : static_cast<int>(rh.hit.primID);
      }
    }
    const double dt = std::chrono::duration<double>(Clock::now() - s).count();
    if (dt < best) best = dt;
  }
  out.trace_seconds = best;
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return out;
}

}  // namespace rtmini::bench
