// Objects no frame shows (view_check.h).
#include "view_check.h"

#include "meso/core/error.h"
#include "meso/geometry/screen_metric.h"
#include "meso/render/displacement.h"
#include "meso/scene/camera.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

namespace meso::app {
namespace {

// The box of the object's patch points; none when no face has a limit surface.
std::optional<std::pair<Vec3, Vec3>> objectBox(const LimitSurface& surface) {
  Vec3 lo(std::numeric_limits<float>::infinity()), hi = -lo;
  bool any = false;
  for (int f = 0; f < surface.numFaces(); ++f) {
    Vec3 faceLo, faceHi;
    if (!surface.faceBox(f, faceLo, faceHi)) continue;
    lo = glm::min(lo, faceLo);
    hi = glm::max(hi, faceHi);
    any = true;
  }
  if (!any) return std::nullopt;
  return std::make_pair(lo, hi);
}

}  // namespace

std::vector<std::string> objectsOutOfView(const Scene& scene, const RenderContext& ctx,
                                          const std::vector<CameraSettings>& cameras) {
  if (cameras.empty()) return {};
  std::vector<ScreenMetric> screens;
  for (const CameraSettings& c : cameras) screens.push_back(Camera(c).screen());
  std::vector<std::string> warnings;
  for (size_t k = 0; k < ctx.objects.size() && k < scene.objects.size(); ++k) {
    const std::optional<std::pair<Vec3, Vec3>> box = objectBox(ctx.objects[k].surface);
    if (!box) continue;
    const float grow = displacementBound(ctx.reliefs[ctx.objects[k].material]);
    const bool seen = std::any_of(screens.begin(), screens.end(), [&](const ScreenMetric& s) {
      return s.boxNearView(box->first, box->second, grow);
    });
    if (seen) continue;
    const Object& o = scene.objects[k];
    warnings.push_back(Error::format(
        o.loc, "",
        fmt::format("the object {} lies outside the view of {}: check camera.position, "
                    "camera.look_at and its transform",
                    o.mesh.filename().string(),
                    cameras.size() == 1 ? "the camera" : "every frame")));
  }
  return warnings;
}

}  // namespace meso::app
