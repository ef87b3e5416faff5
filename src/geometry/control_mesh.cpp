// The control cage of a subdivision surface (shared/DESIGN.md section 1: the macro scale).
#include "meso/geometry/control_mesh.h"

namespace meso {

void transformControlMesh(ControlMesh& mesh, const Mat4& transform) {
  for (Vec3& p : mesh.positions) p = Vec3(transform * Vec4(p, 1.0f));
}

}  // namespace meso
