// An Embree 3 triangle scene (shared/DESIGN.md section 5: the tessellated surface is traced by
// Embree) with robust, watertight closest-hit queries.
#include "meso/geometry/ray_scene.h"

#include "meso/core/error.h"

#include <embree3/rtcore.h>

#include <cstring>
#include <mutex>
#include <string>

namespace meso {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  int numMeshes = 0;
  std::mutex errorMutex;
  std::string firstError;  // the first Embree error not yet reported, empty if none

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  // Embree reports API errors through this callback rather than return codes.
  static void onError(void* self, RTCError code, const char* message) {
    auto* impl = static_cast<Impl*>(self);
    std::lock_guard<std::mutex> lock(impl->errorMutex);
    if (impl->firstError.empty())
      impl->firstError = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                         (message ? message : "(no message)");
  }

  void throwIfError() {
    std::lock_guard<std::mutex> lock(errorMutex);
    if (firstError.empty()) return;
    std::string message;
    message.swap(firstError);
    throw Error(message);
  }
};

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device)
    throw Error("Embree device creation failed (error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl_->device, &Impl::onError, impl_.get());
  impl_->scene = rtcNewScene(impl_->device);
  // ROBUST makes the triangle test watertight: a ray through a shared edge or vertex of two
  // triangles hits one of them, so tessellated closed surfaces never leak.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  // The scene is rebuilt for every frame of a fly-through: MEDIUM builds faster than HIGH at a
  // small cost in ray rate.
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);
  impl_->throwIfError();
}

RayScene::~RayScene() = default;

int RayScene::addMesh(const TessellatedMesh& mesh) {
  const unsigned id = static_cast<unsigned>(impl_->numMeshes);
  const size_t numTriangles = mesh.indices.size() / 3;
  ++impl_->numMeshes;
  // An empty mesh keeps its index but needs no geometry (Embree rejects empty buffers).
  if (numTriangles == 0) return static_cast<int>(id);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree owns these copies (padded as its SIMD loads need), so `mesh` may go away afterwards.
  void* vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           sizeof(Vec3), mesh.positions.size());
  if (vertices) std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
  void* indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                          3 * sizeof(uint32_t), numTriangles);
  if (indices) std::memcpy(indices, mesh.indices.data(), numTriangles * 3 * sizeof(uint32_t));
  rtcCommitGeometry(geometry);
  // Attaching by ID makes the geometry ID of a hit the index returned here.
  rtcAttachGeometryByID(impl_->scene, geometry, id);
  rtcReleaseGeometry(geometry);  // the scene holds the reference now
  impl_->throwIfError();
  numTriangles_ += numTriangles;
  return static_cast<int>(id);
}

void RayScene::commit() {
  rtcCommitScene(impl_->scene);
  impl_->throwIfError();
}

bool RayScene::intersect(const Ray& ray, RayHit& hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x;
  rh.ray.dir_y = ray.direction.y;
  rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = ray.tNear;
  rh.ray.tfar = ray.tFar;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.mesh = static_cast<int>(rh.hit.geomID);
  hit.triangle = static_cast<int>(rh.hit.primID);
  hit.b1 = rh.hit.u;
  hit.b2 = rh.hit.v;
  return true;
}

}  // namespace meso
