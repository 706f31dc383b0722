// Embree 3 or 4 scenes for the benchmark. See embree.hpp.
//
// RAYKIT_BENCH_EMBREE is Embree's major version (bench/CMakeLists.txt), or 0
// without Embree. The two versions differ here only in the header's folder
// and in the query: Embree 3 takes an RTCIntersectContext, Embree 4 optional
// RTCIntersectArguments (left out: the defaults).

#include "embree.hpp"

#if RAYKIT_BENCH_EMBREE

#include <cstdio>
#include <deque>
#include <limits>

#if RAYKIT_BENCH_EMBREE >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

namespace raykit::bench::embree {

struct Scene {
    RTCScene handle = nullptr;
};

namespace {

void on_error(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "raykit_bench: Embree error %d: %s\n", static_cast<int>(code), message ? message : "");
}

/// The device and every scene made on it, released in order at exit.
struct Registry {
    RTCDevice device = nullptr;
    std::deque<Scene> scenes;  // stable addresses for the pointers handed out

    Registry() {
        // One thread: the scenes are tiny and the machine may be shared.
        device = rtcNewDevice("threads=1");
        if (device) rtcSetDeviceErrorFunction(device, on_error, nullptr);
    }
    ~Registry() {
        for (Scene& s : scenes) rtcReleaseScene(s.handle);
        if (device) rtcReleaseDevice(device);
    }
    Registry(const Registry&) = delete;
    Registry& operator=(const Registry&) = delete;
};

Registry& registry() {
    static Registry r;
    return r;
}

RTCDevice device() { return registry().device; }

const Scene* commit(RTCGeometry geometry) {
    rtcCommitGeometry(geometry);
    RTCScene scene = rtcNewScene(device());
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    registry().scenes.push_back({scene});
    return &registry().scenes.back();
}

}  // namespace

bool available() { return device() != nullptr; }

std::string status() {
    if (!available()) return "Embree " RTC_VERSION_STRING " is installed but rtcNewDevice failed";
    return "Embree " RTC_VERSION_STRING;
}

const Scene* quads(const std::vector<Rect3>& rects) {
    RTCGeometry g = rtcNewGeometry(device(), RTC_GEOMETRY_TYPE_QUAD);
    const auto n = rects.size();
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * n));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), n));
    for (std::size_t i = 0; i < n; ++i) {
        const Rect3& r = rects[i];
        int u, v;
        other_axes(r.axis, u, v);
        // The four corners in order around the rectangle.
        const float corners[4][2] = {{r.lo[0], r.lo[1]}, {r.hi[0], r.lo[1]}, {r.hi[0], r.hi[1]}, {r.lo[0], r.hi[1]}};
        for (int k = 0; k < 4; ++k) {
            float* p = vertices + 3 * (4 * i + k);
            p[r.axis] = r.offset;
            p[u] = corners[k][0];
            p[v] = corners[k][1];
            indices[4 * i + k] = static_cast<unsigned>(4 * i + k);
        }
    }
    return commit(g);
}

const Scene* sphere(const Vec3<float>& centre, float radius) {
    RTCGeometry g = rtcNewGeometry(device(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* point = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    point[0] = centre.x;
    point[1] = centre.y;
    point[2] = centre.z;
    point[3] = radius;
    return commit(g);
}

BoxHit intersect(const Scene* scene, const Vec3<float>& o, const Vec3<float>& d, float tmin) {
    RTCRayHit rh;  // RTC_ALIGN(16) in its declaration
    rh.ray.org_x = o.x;
    rh.ray.org_y = o.y;
    rh.ray.org_z = o.z;
    rh.ray.tnear = tmin;
    rh.ray.dir_x = d.x;
    rh.ray.dir_y = d.y;
    rh.ray.dir_z = d.z;
    rh.ray.time = 0;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if RAYKIT_BENCH_EMBREE >= 4
    rtcIntersect1(scene->handle, &rh);
#else
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene->handle, &context, &rh);
#endif
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
    return {true, static_cast<int>(rh.hit.primID), rh.ray.tfar};
}

bool packets(int width) {
    if (!available()) return false;
    const RTCDeviceProperty p = width == 16 ? RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED
                                            : RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED;
    return (width == 8 || width == 16) && rtcGetDeviceProperty(device(), p) != 0;
}

namespace {

/// W rays at a time through Embree's packet query; RH is RTCRayHit8 or 16.
template <int W, class RH>
void packet_loop(RTCScene scene, const float* const o[3], const float* const d[3], std::size_t begin,
                 std::size_t end, float tmin, float* t, float* rect) {
    alignas(64) int valid[W];
    for (int k = 0; k < W; ++k) valid[k] = -1;  // every lane active
    alignas(64) RH rh;
    for (std::size_t i = begin; i < end; i += W) {
        for (int k = 0; k < W; ++k) {
            rh.ray.org_x[k] = o[0][i + k], rh.ray.org_y[k] = o[1][i + k], rh.ray.org_z[k] = o[2][i + k];
            rh.ray.dir_x[k] = d[0][i + k], rh.ray.dir_y[k] = d[1][i + k], rh.ray.dir_z[k] = d[2][i + k];
            rh.ray.tnear[k] = tmin;
            rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
            rh.ray.time[k] = 0;
            rh.ray.mask[k] = ~0u;
            rh.ray.id[k] = 0;
            rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
#if RAYKIT_BENCH_EMBREE >= 4
        if constexpr (W == 16) rtcIntersect16(valid, scene, &rh);
        else rtcIntersect8(valid, scene, &rh);
#else
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        if constexpr (W == 16) rtcIntersect16(valid, scene, &context, &rh);
        else rtcIntersect8(valid, scene, &context, &rh);
#endif
        for (int k = 0; k < W; ++k) {
            const bool hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
            t[i + k] = hit ? rh.ray.tfar[k] : 0.0f;
            rect[i + k] = hit ? static_cast<float>(rh.hit.primID[k]) : -1.0f;
        }
    }
}

}  // namespace

void intersect_packets(const Scene* scene, int width, const float* const o[3], const float* const d[3],
                       std::size_t begin, std::size_t end, float tmin, float* t, float* rect) {
    if (width == 16) packet_loop<16, RTCRayHit16>(scene->handle, o, d, begin, end, tmin, t, rect);
    else packet_loop<8, RTCRayHit8>(scene->handle, o, d, begin, end, tmin, t, rect);
}

}  // namespace raykit::bench::embree

#else  // no Embree

namespace raykit::bench::embree {

struct Scene {};

bool available() { return false; }
std::string status() { return "Embree 3 or 4 not found (Debian: libembree-dev); its comparison is skipped"; }
const Scene* quads(const std::vector<Rect3>&) { return nullptr; }
const Scene* sphere(const Vec3<float>&, float) { return nullptr; }
BoxHit intersect(const Scene*, const Vec3<float>&, const Vec3<float>&, float) { return {}; }
bool packets(int) { return false; }
void intersect_packets(const Scene*, int, const float* const[3], const float* const[3], std::size_t, std::size_t, float,
                       float*, float*) {}

}  // namespace raykit::bench::embree

#endif
