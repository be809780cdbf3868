// Owning handles for Embree objects and readable error names, shared by the reference tracer and
// the BVH builder.
#pragma once
#include <memory>

#include <embree3/rtcore.h>

namespace penumbra::embree {

struct DeviceRelease {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneRelease {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
struct GeometryRelease {
  void operator()(RTCGeometry g) const { rtcReleaseGeometry(g); }
};
struct BvhRelease {
  void operator()(RTCBVH b) const { rtcReleaseBVH(b); }
};
using DevicePtr = std::unique_ptr<RTCDeviceTy, DeviceRelease>;
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneRelease>;
using GeometryPtr = std::unique_ptr<RTCGeometryTy, GeometryRelease>;
using BvhPtr = std::unique_ptr<RTCBVHTy, BvhRelease>;

inline const char* errorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

}  // namespace penumbra::embree
