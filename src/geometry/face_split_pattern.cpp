// The sub-quads of a split quad face and their points (DiagSplit's split with shared edge rates,
// Fisher et al. 2009, inside one face): each sub-quad is a Bfr pattern with four edge rates whose
// coordinates are mapped bilinearly from its corners into the face. Its edges on the face boundary
// reuse the mesh-edge points; the split lines' points are created once by the face.
#include "face_split.h"
#include "limit_surface_impl.h"

#include <algorithm>
#include <cmath>

namespace meso {

using OpenSubdiv::Bfr::Tessellation;

namespace {

// round(i R / n): n <= R, so consecutive values differ by at least one.
int splitIndex(int i, int R, int n) {
  return static_cast<int>(std::lround(static_cast<double>(i) * R / n));
}

Tessellation subQuadTessellation(const OpenSubdiv::Bfr::Parameterization& param, const int r[6]) {
  Tessellation::Options options;
  options.SetFacetSize(3);
  if (std::all_of(r, r + 6, [&](int x) { return x == r[0]; }))
    return Tessellation(param, r[0], options);
  return Tessellation(param, 6, r, options);
}

// Where lines ab and cd cross (they do: a column and a row of the split grid).
Vec2 crossing(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const Vec2 r = b - a, s = d - c, w = c - a;
  const float det = r.x * s.y - r.y * s.x;
  return a + r * ((w.x * s.y - w.y * s.x) / det);
}

}  // namespace

SplitPattern splitPattern(const int R[4], const FaceSplit& split) {
  SplitPattern p;
  p.nu = split.nu;
  p.nv = split.nv;
  std::copy(R, R + 4, p.R);
  for (int i = 0; i <= p.nu; ++i) {
    p.bottom[i] = splitIndex(i, R[0], p.nu);
    p.top[i] = R[2] - splitIndex(i, R[2], p.nu);
  }
  for (int j = 0; j <= p.nv; ++j) {
    p.right[j] = splitIndex(j, R[1], p.nv);
    p.left[j] = R[3] - splitIndex(j, R[3], p.nv);
  }
  p.numCrossings = (p.nu - 1) * (p.nv - 1);
  int next = p.numCrossings;
  const auto ask = [&](const std::vector<int>& a, int i, int j) { return a[j * p.nu + i]; };
  for (int j = 1; j < p.nv; ++j)
    for (int i = 0; i < p.nu; ++i) {
      p.rowRate.push_back(std::max(ask(split.askU, i, j - 1), ask(split.askU, i, j)));
      p.rowFirst.push_back(next);
      next += p.rowRate.back() - 1;
    }
  for (int i = 1; i < p.nu; ++i)
    for (int j = 0; j < p.nv; ++j) {
      p.colRate.push_back(std::max(ask(split.askV, i - 1, j), ask(split.askV, i, j)));
      p.colFirst.push_back(next);
      next += p.colRate.back() - 1;
    }
  p.numLinePoints = next;
  p.askU = split.askU;
  p.askV = split.askV;
  return p;
}

void SplitPattern::subRates(int i, int j, int r[6]) const {
  r[0] = j == 0 ? bottom[i + 1] - bottom[i] : rowRate[(j - 1) * nu + i];
  r[1] = i + 1 == nu ? right[j + 1] - right[j] : colRate[i * nv + j];
  r[2] = j + 1 == nv ? top[i] - top[i + 1] : rowRate[j * nu + i];
  r[3] = i == 0 ? left[j] - left[j + 1] : colRate[(i - 1) * nv + j];
  r[4] = askU[j * nu + i];
  r[5] = askV[j * nu + i];
}

void EdgeRateTessellator::countSplitFace(size_t k, const std::vector<int>& edgeRates,
                                         const FaceSplit& split, FaceScratch& scratch) {
  const int f = faces_[k];
  faceTessellation(f, edgeRates, scratch);  // the face's rates
  const SplitPattern pattern = splitPattern(scratch.rates.data(), split);
  size_t points = ownedBoundaryPoints(f, edgeRates) + static_cast<size_t>(pattern.numLinePoints);
  size_t facets = 0, gridOnly = 0;
  scratch.rates.resize(6);
  for (int j = 0; j < pattern.nv; ++j)
    for (int i = 0; i < pattern.nu; ++i) {
      pattern.subRates(i, j, scratch.rates.data());
      const Tessellation tess = subQuadTessellation(impl_.faces[f].param, scratch.rates.data());
      points += static_cast<size_t>(tess.GetNumInteriorCoords());
      facets += static_cast<size_t>(tess.GetNumFacets());
      gridOnly += gridOnlyFacets(f, tess, scratch);
    }
  numPoints_[k] = points;
  numFacets_[k] = facets - gridOnly;
  numGridOnly_[k] = gridOnly;
}

// The split grid's nodes (Bfr uv; the boundary ones are the face's own boundary coordinates) and
// the points of the split lines, which this face creates: crossings, then each segment's inner
// points evenly spaced in uv (rows along +u, columns along +v), as its sub-quads' edges place them.
void EdgeRateTessellator::placeSplitLines(int f, const SplitPattern& p, int base,
                                          FaceScratch& scratch) {
  const int nu = p.nu, nv = p.nv;
  const int off[4] = {0, p.R[0], p.R[0] + p.R[1], p.R[0] + p.R[1] + p.R[2]};
  const int total = off[3] + p.R[3];
  const auto boundaryUv = [&](int edge, int index) {
    const int b = (off[edge] + index) % total;
    return Vec2(scratch.coords[2 * b], scratch.coords[2 * b + 1]);
  };
  scratch.nodeUv.resize(static_cast<size_t>(nu + 1) * (nv + 1));
  const auto node = [&](int i, int j) -> Vec2& { return scratch.nodeUv[j * (nu + 1) + i]; };
  for (int i = 0; i <= nu; ++i) node(i, 0) = boundaryUv(0, p.bottom[i]);
  for (int i = 0; i <= nu; ++i) node(i, nv) = boundaryUv(2, p.top[i]);
  for (int j = 1; j < nv; ++j) node(0, j) = boundaryUv(3, p.left[j]);
  for (int j = 1; j < nv; ++j) node(nu, j) = boundaryUv(1, p.right[j]);
  scratch.linePoint.resize(p.numLinePoints);
  scratch.lineSt.resize(p.numLinePoints);
  const auto place = [&](int local, Vec2 uv) {
    scratch.linePoint[local] = base + local;
    scratch.lineSt[local] = impl_.bfrToChart(f, uv);
    samples_[base + local] = {.face = f, .st = scratch.lineSt[local]};
  };
  for (int j = 1; j < nv; ++j)
    for (int i = 1; i < nu; ++i) {
      node(i, j) = crossing(node(i, 0), node(i, nv), node(0, j), node(nu, j));
      place((j - 1) * (nu - 1) + (i - 1), node(i, j));
    }
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int s = (j - 1) * nu + i, r = p.rowRate[s];
      for (int m = 1; m < r; ++m)
        place(p.rowFirst[s] + m - 1, glm::mix(node(i, j), node(i + 1, j), float(m) / float(r)));
    }
  for (int i = 1; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int s = (i - 1) * nv + j, r = p.colRate[s];
      for (int m = 1; m < r; ++m)
        place(p.colFirst[s] + m - 1, glm::mix(node(i, j), node(i, j + 1), float(m) / float(r)));
    }
}

// Output point and st of each boundary coordinate of sub-quad (i, j), in Bfr's order: corner
// (i, j), its bottom edge along +u, corner (i + 1, j), right edge along +v, and so on.
void EdgeRateTessellator::placeSubQuadBoundary(const SplitPattern& p, int i, int j,
                                               FaceScratch& scratch) const {
  const int off[4] = {0, p.R[0], p.R[0] + p.R[1], p.R[0] + p.R[1] + p.R[2]};
  const int total = off[3] + p.R[3];
  int b = 0;
  const auto onFace = [&](int edge, int index) {
    const int c = (off[edge] + index) % total;
    scratch.point[b] = scratch.facePoint[c];
    scratch.st[b++] = scratch.faceSt[c];
  };
  const auto onLine = [&](int local) {
    scratch.point[b] = scratch.linePoint[local];
    scratch.st[b++] = scratch.lineSt[local];
  };
  // Corner (ci, cj): on the face boundary or a crossing.
  const auto corner = [&](int ci, int cj) {
    if (cj == 0) return onFace(0, p.bottom[ci]);
    if (cj == p.nv) return onFace(2, p.top[ci]);
    if (ci == 0) return onFace(3, p.left[cj]);
    if (ci == p.nu) return onFace(1, p.right[cj]);
    onLine((cj - 1) * (p.nu - 1) + (ci - 1));
  };
  int r[6];
  p.subRates(i, j, r);
  corner(i, j);
  for (int m = 1; m < r[0]; ++m)
    j == 0 ? onFace(0, p.bottom[i] + m) : onLine(p.rowFirst[(j - 1) * p.nu + i] + m - 1);
  corner(i + 1, j);
  for (int m = 1; m < r[1]; ++m)
    i + 1 == p.nu ? onFace(1, p.right[j] + m) : onLine(p.colFirst[i * p.nv + j] + m - 1);
  corner(i + 1, j + 1);
  for (int m = 1; m < r[2]; ++m)
    j + 1 == p.nv ? onFace(2, p.top[i + 1] + m) : onLine(p.rowFirst[j * p.nu + i] + r[2] - m - 1);
  corner(i, j + 1);
  for (int m = 1; m < r[3]; ++m)
    i == 0 ? onFace(3, p.left[j + 1] + m) : onLine(p.colFirst[(i - 1) * p.nv + j] + r[3] - m - 1);
}

// The face's own boundary points as for an unsplit face, then its split lines, then each
// sub-quad's interior (sub-quads row by row), each written as a Bfr pattern (emitPattern).
void EdgeRateTessellator::emitSplitFace(size_t k, const std::vector<int>& edgeRates,
                                        const FaceSplit& split, FaceScratch& scratch,
                                        TessellatedMesh& out, std::vector<TriangleGrid>* grids) {
  const int f = faces_[k];
  const Tessellation faceTess = faceTessellation(f, edgeRates, scratch);
  beginFace(k, faceTess, edgeRates, true, scratch);
  const SplitPattern p = splitPattern(scratch.rates.data(), split);
  scratch.facePoint = scratch.point;
  scratch.faceSt = scratch.st;
  int base = static_cast<int>(pointOffset_[k] + ownedBoundaryPoints(f, edgeRates));
  placeSplitLines(f, p, base, scratch);
  base += p.numLinePoints;
  size_t t = facetOffset_[k];
  scratch.rates.resize(6);
  for (int j = 0; j < p.nv; ++j)
    for (int i = 0; i < p.nu; ++i) {
      p.subRates(i, j, scratch.rates.data());
      const Tessellation tess = subQuadTessellation(impl_.faces[f].param, scratch.rates.data());
      const Vec2 c00 = scratch.nodeUv[j * (p.nu + 1) + i],
                 c10 = scratch.nodeUv[j * (p.nu + 1) + i + 1];
      const Vec2 c01 = scratch.nodeUv[(j + 1) * (p.nu + 1) + i];
      const Vec2 c11 = scratch.nodeUv[(j + 1) * (p.nu + 1) + i + 1];
      const int numCoords = tess.GetNumCoords();
      scratch.coords.resize(2 * static_cast<size_t>(numCoords));
      tess.GetCoords(scratch.coords.data());
      scratch.point.resize(numCoords);
      scratch.st.resize(numCoords);
      placeSubQuadBoundary(p, i, j, scratch);
      for (int c = tess.GetNumBoundaryCoords(); c < numCoords; ++c) {
        const float s = scratch.coords[2 * c], v = scratch.coords[2 * c + 1];
        const Vec2 uv = glm::mix(glm::mix(c00, c10, s), glm::mix(c01, c11, s), v);
        scratch.st[c] = impl_.bfrToChart(f, uv);
      }
      TriangleGrid grid;
      t = emitPattern(f, tess, scratch, base, t, out, grids ? &grid : nullptr);
      if (grids && grid.width > 0) grids->push_back(grid);
      base += tess.GetNumInteriorCoords();
    }
}

}  // namespace meso
