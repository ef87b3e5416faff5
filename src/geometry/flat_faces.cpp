// Flat faces drawn by two triangles (flat_faces.h).
#include "meso/geometry/flat_faces.h"

#include "limit_surface_impl.h"
#include "meso/core/error.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace meso {
namespace {

// Whether P(st) = P(c0) + A (st - c0) at every test point, A fitted from corners 0, 1 and the last.
bool isAffine(const LimitSurface& surface, int face) {
  const int n = surface.faceSize(face);
  if (n < 3) return false;
  std::vector<Vec2> st(static_cast<size_t>(n));
  std::vector<Vec3> P(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    st[k] = surface.cornerSt(face, k);
    P[k] = surface.evaluate(face, st[k]).P;
  }
  const Vec2 a = st[1] - st[0], b = st[n - 1] - st[0];
  const float det = a.x * b.y - a.y * b.x;
  if (!(std::abs(det) > 1e-12f)) return false;
  const Vec3 da = P[1] - P[0], db = P[n - 1] - P[0];
  float size = 0.0f, far = 0.0f;
  for (int k = 0; k < n; ++k) {
    size = std::max(size, glm::length(P[k] - P[0]));
    far = std::max({far, std::abs(P[k].x), std::abs(P[k].y), std::abs(P[k].z)});
  }
  if (!(size > 0.0f) || !std::isfinite(size) || !std::isfinite(far)) return false;
  // Relative to the face, and at least a few units in the last place of its coordinates (a face
  // 300 units from the origin evaluates to about 3e-5).
  const float tolerance = 1e-5f * size + 8.0f * std::numeric_limits<float>::epsilon() * far;
  // A bilinear patch on the unit square departs from the plane of corners 0, 1 and 3 by s t times
  // its twist P0 - P1 + P2 - P3, most at corner 2: the corners decide.
  if (n == 4 && surface.impl().faces[face].bilinear)
    return glm::length(P[0] - P[1] + P[2] - P[3]) <= tolerance;
  // st = c0 + x a + y b  =>  P = P0 + x da + y db.
  const auto affine = [&](Vec2 p) {
    const Vec2 d = p - st[0];
    const float x = (d.x * b.y - d.y * b.x) / det, y = (a.x * d.y - a.y * d.x) / det;
    return P[0] + x * da + y * db;
  };
  Vec2 centre(0.0f);
  for (const Vec2& c : st) centre += c / static_cast<float>(n);
  std::vector<Vec2> tests(st.begin(), st.end());
  for (int k = 0; k < n; ++k) {
    const Vec2 mid = 0.5f * (st[k] + st[(k + 1) % n]);
    tests.push_back(mid);
    for (float w : {0.3f, 0.7f}) tests.push_back(centre + w * (st[k] - centre));
    tests.push_back(centre + 0.5f * (mid - centre));
  }
  tests.push_back(centre);
  for (const Vec2& p : tests)
    if (!(glm::length(surface.evaluate(face, p).P - affine(p)) <= tolerance)) return false;
  return true;
}

}  // namespace

bool faceIsAffine(const LimitSurface& surface, int face) { return isAffine(surface, face); }

std::vector<uint8_t> affineFaces(const LimitSurface& surface) {
  std::vector<uint8_t> out(static_cast<size_t>(surface.numFaces()), 0);
  tbb::parallel_for(0, surface.numFaces(), [&](int f) {
    out[f] = surface.hasLimitSurface(f) && isAffine(surface, f) ? 1 : 0;
  });
  return out;
}

TessellatedMesh tessellateSmooth(const LimitSurface& surface, int rate, uint64_t memoryLimitBytes,
                                 const std::string& where, double heldBytes,
                                 const std::vector<uint8_t>* affineIn) {
  if (rate < 1)
    throw Error("tessellation rate must be at least 1 (got " + std::to_string(rate) + ")");
  EdgeRateTessellator tessellator(surface);
  std::vector<int> rates(static_cast<size_t>(tessellator.numEdges()), 1);
  const std::vector<uint8_t> computed = affineIn ? std::vector<uint8_t>() : affineFaces(surface);
  const std::vector<uint8_t>& affine = affineIn ? *affineIn : computed;
  if (affine.size() != static_cast<size_t>(surface.numFaces()))
    throw Error("tessellateSmooth: " + std::to_string(affine.size()) + " affine flags for " +
                std::to_string(surface.numFaces()) + " faces");
  const LimitSurface::Impl::Topology& base = surface.impl().topology;
  // Bfr at rate R: 2 R^2 triangles a quad, R^2 a triangle, n R^2 / 2 an n-gon (n quads of R / 2);
  // a flat face at rate 1: 2 triangles a quad, n - 2 otherwise (counted as n, an upper bound).
  double triangles = 0.0;
  int curved = 0;
  for (int f = 0; f < surface.numFaces(); ++f) {
    if (!surface.hasLimitSurface(f)) continue;
    const int n = surface.faceSize(f);
    if (affine[f]) {
      triangles += n == 4 ? 2 : n;
      continue;
    }
    ++curved;
    triangles += (n == 3 ? 1.0 : n == 4 ? 2.0 : 0.5 * n) * double(rate) * double(rate);
    for (int e : base.faceEdges(f)) rates[e] = rate;
  }
  requireMemoryWithin(memoryLimitBytes, heldBytes + triangles * kBytesPerMicropolygon, where,
                      "render.tessellation_rate",
                      "about " + std::to_string(static_cast<long long>(triangles)) +
                          " triangles at rate " + std::to_string(rate) + " on " +
                          std::to_string(curved) + " curved faces, drawn undisplaced" +
                          (heldBytes > 0.0 ? ", beside " + formatMib(heldBytes) +
                                                 " held for the film, the tables, the limit "
                                                 "surfaces and the process so far"
                                           : ""));
  return tessellator.tessellate(rates, nullptr);
}

}  // namespace meso
