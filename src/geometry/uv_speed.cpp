#include "meso/geometry/uv_speed.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace meso {

UvSpeed::UvSpeed(const ControlMesh& mesh, const LimitSurface& surface) {
  const int faces = std::min(mesh.numFaces(), surface.numFaces());
  first_.assign(static_cast<size_t>(faces) + 1, 0);
  for (int f = 0; f < faces; ++f) first_[f + 1] = first_[f] + mesh.faceSizes[f];
  const size_t corners = static_cast<size_t>(first_[faces]);
  std::vector<float> own(corners, 0.0f);
  kind_.assign(static_cast<size_t>(faces), kMean);
  int triangles = 0;
  for (int f = 0; f < faces; ++f) triangles += mesh.faceSizes[f] == 3;
  if (triangles > 0) {
    triangle_.assign(static_cast<size_t>(faces), -1);
    triangleSt_.assign(3 * static_cast<size_t>(triangles), Vec2(0.0f));
    for (int f = 0, t = 0; f < faces; ++f)
      if (mesh.faceSizes[f] == 3) triangle_[f] = t++;
  }
  // Each face's corners in parallel (evaluate is thread-safe), then the vertex means in order.
  tbb::parallel_for(tbb::blocked_range<int>(0, faces), [&](const tbb::blocked_range<int>& range) {
    // A face with the derivatives of one evaluated before has its corner lengths.
    DerivativeSweep sweep(surface);
    for (int f = range.begin(); f != range.end(); ++f) {
      const int n = mesh.faceSizes[f];
      if (!surface.hasLimitSurface(f) || surface.faceSize(f) != n) continue;
      const int same = sweep.sameAs(f);
      Vec2 st[4];
      for (int k = 0; k < n; ++k) {
        const size_t c = static_cast<size_t>(first_[f] + k);
        const Vec2 corner = surface.cornerSt(f, k);
        if (k < 4) st[k] = corner;
        if (same >= 0) {
          own[c] = own[static_cast<size_t>(first_[same] + k)];
          continue;
        }
        const SurfacePoint sp = surface.evaluate(f, corner);
        const float length = std::max(glm::length(sp.Pu), glm::length(sp.Pv));
        if (std::isfinite(length)) own[c] = length;
      }
      if (n == 4 && st[0] == Vec2(0, 0) && st[1] == Vec2(1, 0) && st[2] == Vec2(1, 1) &&
          st[3] == Vec2(0, 1)) {
        kind_[f] = kUnitQuad;
      } else if (n == 3) {
        kind_[f] = kTriangle;
        std::copy(st, st + 3, triangleSt_.begin() + 3 * static_cast<size_t>(triangle_[f]));
      }
    }
  });
  std::vector<double> sum(mesh.positions.size(), 0.0);
  std::vector<int> count(mesh.positions.size(), 0);
  for (size_t c = 0; c < corners; ++c)
    if (own[c] > 0.0f) {
      sum[static_cast<size_t>(mesh.faceVertices[c])] += own[c];
      ++count[static_cast<size_t>(mesh.faceVertices[c])];
    }
  corner_.assign(corners, 0.0f);
  for (size_t c = 0; c < corners; ++c) {
    const int v = mesh.faceVertices[c];
    corner_[c] = count[v] > 0 ? static_cast<float>(sum[v] / count[v]) : own[c];
  }
}

float UvSpeed::at(int face, Vec2 st) const {
  if (empty() || face < 0 || face + 1 >= static_cast<int>(first_.size())) return 0.0f;
  const float* c = &corner_[first_[face]];
  const int n = first_[face + 1] - first_[face];
  if (kind_[face] == kUnitQuad) {
    // Bilinear over the quad's corners (0,0), (1,0), (1,1), (0,1) in patch coordinates.
    const float x = std::clamp(st.x, 0.0f, 1.0f), y = std::clamp(st.y, 0.0f, 1.0f);
    return (1 - x) * (1 - y) * c[0] + x * (1 - y) * c[1] + x * y * c[2] + (1 - x) * y * c[3];
  }
  if (kind_[face] == kTriangle) {
    // Barycentric over the triangle of its corners' patch coordinates.
    const Vec2* s = &triangleSt_[3 * static_cast<size_t>(triangle_[face])];
    const Vec2 e1 = s[1] - s[0], e2 = s[2] - s[0], p = st - s[0];
    const float det = e1.x * e2.y - e1.y * e2.x;
    if (std::abs(det) > 1e-12f) {
      const float b1 = std::clamp((p.x * e2.y - p.y * e2.x) / det, 0.0f, 1.0f);
      const float b2 = std::clamp((e1.x * p.y - e1.y * p.x) / det, 0.0f, 1.0f - b1);
      return (1 - b1 - b2) * c[0] + b1 * c[1] + b2 * c[2];
    }
  }
  float mean = 0.0f;
  for (int k = 0; k < n; ++k) mean += c[k];
  return n > 0 ? mean / static_cast<float>(n) : 0.0f;
}

size_t UvSpeed::memoryBytes() const {
  return first_.capacity() * sizeof(int) + corner_.capacity() * sizeof(float) + kind_.capacity() +
         triangle_.capacity() * sizeof(int) + triangleSt_.capacity() * sizeof(Vec2);
}

float UvSpeed::faceMax(int face) const {
  if (empty() || face < 0 || face + 1 >= static_cast<int>(first_.size())) return 0.0f;
  float m = 0.0f;
  for (int c = first_[face]; c < first_[face + 1]; ++c) m = std::max(m, corner_[c]);
  return m;
}

}  // namespace meso
