// Where to split a face (DiagSplit, Fisher et al. 2009, splits where the rate changes across a
// patch): with one rate per mesh edge, a face is otherwise diced everywhere at the density of its
// densest point in view, also where it lies out of view or recedes far in depth.
#include "face_split.h"

#include "edge_measure.h"
#include "limit_surface_impl.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace meso {

namespace {

using Cell = SplitPlan::Cell;

// Split only where parts of a face differ by more than this in pixel density.
constexpr float kSplitDensityRatio = 2.0f;

struct CellSamples {
  Vec3 P[3][3];  // [row along v][column along u]
};

// Segments that keep the polyline a0 a2 within `tolerance` pixels of the curve through a1 (a
// chord's deviation falls as 1 / n^2 with n segments), as edge_measure.cpp measures edges.
float coarseSegments(const ScreenMetric& screen, Vec3 a0, Vec3 a1, Vec3 a2, float tolerance) {
  const float z = screen.depth(a1);
  if (!(z >= screen.nearDistance)) return 0.0f;
  const float deviation = glm::length(a1 - 0.5f * (a0 + a2)) * screen.pixelsPerUnit(z);
  return std::isfinite(deviation) ? std::sqrt(deviation / tolerance) : 0.0f;
}

// A cell is in view when the box of its samples, grown by a ball of the displacement bound plus
// twice its sag, is: samples are not a conservative hull, but the smooth limit patch between
// samples half a cell apart leaves their box by its sag only. The sag is the largest deviation of
// a middle sample from the chord of its row or column (a quadratic between the samples leaves
// their polyline by a quarter of that), plus 1e-3 of the box's diagonal for rounding; on a plane
// the box holds the patch exactly, so a cell just below the view is not diced for it.
// It is diced when it is in view and relief may be raised in that grown box (FaceDicing::
// raisesBox). Its density is the largest pixelDensity of its samples in view or, when none is
// (relief may rise into view), of all its samples in front of the eye.
Cell measureCell(const CellSamples& c, const ScreenMetric& screen, const DicingSettings& s,
                 const FaceDicing& faces, int f, float bound, float& density) {
  Cell cell;
  Vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
  float seen = 0.0f, front = 0.0f;
  for (const auto& row : c.P)
    for (const Vec3& p : row) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      if (screen.pointInView(p)) seen = std::max(seen, screen.pixelDensity(p));
      if (screen.depth(p) >= screen.nearDistance) front = std::max(front, screen.pixelDensity(p));
    }
  float sag = 0.0f;
  for (int k = 0; k < 3; ++k) {
    sag = std::max(sag, glm::length(c.P[k][1] - 0.5f * (c.P[k][0] + c.P[k][2])));
    sag = std::max(sag, glm::length(c.P[1][k] - 0.5f * (c.P[0][k] + c.P[2][k])));
  }
  const float grow = bound + 2.0f * sag + 1e-3f * glm::length(hi - lo);
  cell.diced = screen.boxNearView(lo, hi, grow) && faces.raisesBox(f, screen.eye, lo, hi, grow);
  cell.distance = boxDistance(screen.eye, lo - Vec3(grow), hi + Vec3(grow));
  if (!std::isfinite(cell.distance)) cell.distance = 0.0f;
  density = seen > 0.0f ? seen : front;
  if (!std::isfinite(density)) density = 0.0f;
  if (s.acrossViewCap < 1.0f) {
    const Vec3 du = c.P[1][2] - c.P[1][0], dv = c.P[2][1] - c.P[0][1];
    const Vec3 n = glm::cross(du, dv);
    const float length = glm::length(n);
    if (length > 0.0f && std::isfinite(length)) {
      cell.capScaleU = acrossViewCapScale(screen, c.P[1][1], n / length, du, s.acrossViewCap);
      cell.capScaleV = acrossViewCapScale(screen, c.P[1][1], n / length, dv, s.acrossViewCap);
    }
  }
  for (int k = 0; k < 3; ++k) {
    const Vec3 u[3] = {c.P[k][0], c.P[k][1], c.P[k][2]}, v[3] = {c.P[0][k], c.P[1][k], c.P[2][k]};
    const bool projected = s.metric == DicingMetric::Projected;
    const float lu = projected
                         ? screen.projectedLength(u[0], u[1]) + screen.projectedLength(u[1], u[2])
                         : (glm::length(u[1] - u[0]) + glm::length(u[2] - u[1])) * density;
    const float lv = projected
                         ? screen.projectedLength(v[0], v[1]) + screen.projectedLength(v[1], v[2])
                         : (glm::length(v[1] - v[0]) + glm::length(v[2] - v[1])) * density;
    cell.lengthU = std::max(cell.lengthU, std::isfinite(lu) ? lu : 0.0f);
    cell.lengthV = std::max(cell.lengthV, std::isfinite(lv) ? lv : 0.0f);
    cell.coarseU =
        std::max(cell.coarseU, coarseSegments(screen, u[0], u[1], u[2], s.coarseTolerance));
    cell.coarseV =
        std::max(cell.coarseV, coarseSegments(screen, v[0], v[1], v[2], s.coarseTolerance));
  }
  return cell;
}

// n x n cells of face f, row by row, from (2n + 1)^2 limit points; their densities beside.
void measureCells(const LimitSurface& surface, const ScreenMetric& screen, const DicingSettings& s,
                  const FaceDicing& faces, int f, int n, float bound, std::vector<Cell>& cells,
                  std::vector<float>& densities) {
  const LimitSurface::Impl& impl = surface.impl();
  const int m = 2 * n + 1;
  std::vector<Vec3> P(static_cast<size_t>(m) * m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const Vec2 uv(float(i) / float(m - 1), float(j) / float(m - 1));
      P[j * m + i] = surface.evaluate(f, impl.bfrToChart(f, uv)).P;
    }
  cells.resize(static_cast<size_t>(n) * n);
  densities.resize(cells.size());
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      CellSamples c;
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) c.P[y][x] = P[(2 * b + y) * m + 2 * a + x];
      cells[b * n + a] = measureCell(c, screen, s, faces, f, bound, densities[b * n + a]);
    }
}

// Whether the n x n cells differ along u (alongU) or v: diced or not, or in density by more than
// kSplitDensityRatio among those diced.
bool cellsDiffer(const std::vector<Cell>& cells, const std::vector<float>& densities, int n,
                 bool alongU) {
  for (int line = 0; line < n; ++line) {
    bool anyIn = false, anyOut = false;
    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
    for (int k = 0; k < n; ++k) {
      const int c = alongU ? line * n + k : k * n + line;
      anyIn = anyIn || cells[c].diced;
      anyOut = anyOut || !cells[c].diced;
      if (!cells[c].diced) continue;
      lo = std::min(lo, densities[c]);
      hi = std::max(hi, densities[c]);
    }
    if ((anyIn && anyOut) || (anyIn && hi > kSplitDensityRatio * lo)) return true;
  }
  return false;
}

bool splittable(const LimitSurface& surface, const FaceDicing& faces,
                const std::vector<char>& inView, int f) {
  return inView[f] && (faces.needsDicing.empty() || faces.needsDicing[f]) &&
         surface.hasLimitSurface(f) &&
         surface.impl().faces[f].param.GetType() == OpenSubdiv::Bfr::Parameterization::QUAD;
}

// The asks of the nu x nv sub-quads of a face planned with kMaxSplit^2 cells: a sub-quad's length
// along u is the largest over its cell rows of the sum along them; texel caps and floors are per
// whole edge, so a sub-quad gets its share. The cap coarsens a sub-quad as its nearest cell, so
// one that reaches nearer than cap.beyond is diced as asked.
void askRates(const Cell* cells, const SplitPlan::Face& face, const DicingSettings& s,
              const CapCoarsening& cap, FaceSplit& split) {
  const int fu = kMaxSplit / split.nu, fv = kMaxSplit / split.nv;
  const int edgeLimit = face.cap > 0 ? std::min(face.cap, s.maxEdgeRate) : s.maxEdgeRate;
  const int limitU = (edgeLimit + split.nu - 1) / split.nu;
  const int limitV = (edgeLimit + split.nv - 1) / split.nv;
  const float floorU = std::ceil(float(face.floor) / float(split.nu));
  const float floorV = std::ceil(float(face.floor) / float(split.nv));
  split.askU.assign(static_cast<size_t>(split.nu) * split.nv, 1);
  split.askV.assign(split.askU.size(), 1);
  for (int j = 0; j < split.nv; ++j)
    for (int i = 0; i < split.nu; ++i) {
      bool diced = false;
      float lengthU = 0.0f, lengthV = 0.0f, coarseU = 0.0f, coarseV = 0.0f;
      float scaleU = 0.0f, scaleV = 0.0f;  // the largest of its cells' (acrossViewCapScale)
      float nearest = std::numeric_limits<float>::infinity();
      // Sums of the sub-quad's cell rows and columns (at most kMaxSplit of each): on the stack, as
      // every face in view is planned several ways.
      std::array<float, kMaxSplit> rowU{}, rowCoarseU{}, colV{}, colCoarseV{};
      for (int b = 0; b < fv; ++b)
        for (int a = 0; a < fu; ++a) {
          const Cell& c = cells[(j * fv + b) * kMaxSplit + i * fu + a];
          diced = diced || c.diced;
          nearest = std::min(nearest, c.distance);
          scaleU = std::max(scaleU, c.capScaleU);
          scaleV = std::max(scaleV, c.capScaleV);
          rowU[b] += c.lengthU;
          rowCoarseU[b] += c.coarseU;
          colV[a] += c.lengthV;
          colCoarseV[a] += c.coarseV;
        }
      for (int b = 0; b < fv; ++b) lengthU = std::max(lengthU, rowU[b]);
      for (int b = 0; b < fv; ++b) coarseU = std::max(coarseU, rowCoarseU[b]);
      for (int a = 0; a < fu; ++a) lengthV = std::max(lengthV, colV[a]);
      for (int a = 0; a < fu; ++a) coarseV = std::max(coarseV, colCoarseV[a]);
      const float coarsening = cap.factor(nearest);
      // Not diced (out of view or too far to raise relief): only the coarse rate, as edges of faces
      // in view that need no dicing.
      int u = toRate(coarseU / coarsening, limitU), v = toRate(coarseV / coarsening, limitV);
      if (diced) {
        // The pixel rate stops at the cap scaled across the view, the floor at the whole cap (as
        // edgeRate does for mesh edges).
        const int pixelLimitU =
            face.cap > 0 ? (scaledCap(edgeLimit, scaleU) + split.nu - 1) / split.nu : limitU;
        const int pixelLimitV =
            face.cap > 0 ? (scaledCap(edgeLimit, scaleV) + split.nv - 1) / split.nv : limitV;
        const float scale = s.dicingRate * coarsening;
        u = std::max(
            {u, toRate(lengthU / scale, pixelLimitU), toRate(floorU / coarsening, limitU)});
        v = std::max(
            {v, toRate(lengthV / scale, pixelLimitV), toRate(floorV / coarsening, limitV)});
      }
      split.askU[j * split.nu + i] = u;
      split.askV[j * split.nu + i] = v;
    }
}

// The split of a face with the fewest triangles, those outside the sub-quads' interior grids
// counted twice (Embree triangles cost several times grid cells): finer splits follow the rate
// more closely but add transitions around every sub-quad.
void chooseSplit(const Cell* cells, SplitPlan::Face& face, const DicingSettings& s) {
  double best = std::numeric_limits<double>::infinity();
  const int mostU = face.nu, mostV = face.nv;
  for (int nu = mostU > 1 ? 2 : 1; nu <= mostU; nu *= 2)
    for (int nv = mostV > 1 ? 2 : 1; nv <= mostV; nv *= 2) {
      FaceSplit trial;
      trial.nu = nu;
      trial.nv = nv;
      askRates(cells, face, s, CapCoarsening{}, trial);
      double cost = 0.0;
      for (size_t q = 0; q < trial.askU.size(); ++q)
        cost += 2.0 * trial.askU[q] * trial.askV[q] + 4.0 * (trial.askU[q] + trial.askV[q]);
      if (cost < best) best = cost, face.nu = nu, face.nv = nv;
    }
}

// A cheap test first, since most faces need no split: the hull of the face's patch points (which
// holds the limit patch) wholly in view and, grown by the displacement bound, wholly near enough
// to raise relief (its farthest corner), and pixel densities at 3 x 3 points within
// kSplitDensityRatio of each other.
bool evenlyInView(const LimitSurface& surface, const ScreenMetric& screen, const FaceDicing& faces,
                  int f, float bound) {
  Vec3 lo, hi;
  if (!surface.faceBox(f, lo, hi)) return false;
  for (int c = 0; c < 8; ++c)
    if (!screen.pointInView(Vec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z)))
      return false;
  if (!faces.raiseDistance.empty()) {
    const Vec3 far =
        glm::max(glm::abs(lo - Vec3(bound) - screen.eye), glm::abs(hi + Vec3(bound) - screen.eye));
    if (!(glm::length(far) < faces.raiseDistance[static_cast<size_t>(f)])) return false;
  }
  float least = std::numeric_limits<float>::infinity(), most = 0.0f;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const Vec2 uv(0.5f * float(i), 0.5f * float(j));
      const float d = screen.pixelDensity(surface.evaluate(f, surface.impl().bfrToChart(f, uv)).P);
      least = std::min(least, d);
      most = std::max(most, d);
    }
  return most <= kSplitDensityRatio * least;
}

}  // namespace

SplitPlan planSplits(const LimitSurface& surface, const ScreenMetric& screen,
                     const DicingSettings& settings, const FaceDicing& faces,
                     const std::vector<char>& inView, float bound) {
  SplitPlan plan;
  plan.faces.resize(surface.numFaces());
  std::vector<std::vector<Cell>> faceCells(surface.numFaces());
  tbb::parallel_for(0, surface.numFaces(), [&](int f) {
    if (!splittable(surface, faces, inView, f) || evenlyInView(surface, screen, faces, f, bound))
      return;
    std::vector<Cell> cells;
    std::vector<float> densities;
    measureCells(surface, screen, settings, faces, f, kMaxSplit, bound, cells, densities);
    const bool anyOut =
        std::any_of(cells.begin(), cells.end(), [](const Cell& c) { return !c.diced; });
    SplitPlan::Face& face = plan.faces[f];
    face.nu = cellsDiffer(cells, densities, kMaxSplit, true) ? kMaxSplit : 1;
    face.nv = cellsDiffer(cells, densities, kMaxSplit, false) ? kMaxSplit : 1;
    // Wholly undiced though its hull is in view and near (its edges are diced for the
    // neighbours): the least split, whose sub-quads all get the coarse rate.
    if (face.nu * face.nv == 1 && anyOut) face.nu = face.nv = 2;
    if (face.nu * face.nv == 1) return;
    face.cap = faces.texelCap.empty() ? 0 : faces.texelCap[f];
    face.floor = faces.texelFloor.empty() ? 0 : faces.texelFloor[f];
    chooseSplit(cells.data(), face, settings);
    faceCells[f] = std::move(cells);
  });
  // Concatenated in face order, so the plan does not depend on the threads.
  for (int f = 0; f < surface.numFaces(); ++f) {
    plan.faces[f].firstCell = plan.cells.size();
    plan.cells.insert(plan.cells.end(), faceCells[f].begin(), faceCells[f].end());
  }
  return plan;
}

namespace {

int floorPow2(int x) {
  int p = 1;
  while (2 * p <= x) p *= 2;
  return p;
}

}  // namespace

float farthestCell(const SplitPlan& plan) {
  float farthest = 0.0f;
  for (const Cell& c : plan.cells) farthest = std::max(farthest, c.distance);
  return farthest;
}

std::vector<FaceSplit> splitsFor(const LimitSurface& surface, const SplitPlan& plan,
                                 const std::vector<int>& edgeRates, const DicingSettings& settings,
                                 const CapCoarsening& cap, int& facesSplit) {
  facesSplit = 0;
  if (plan.cells.empty()) return {};
  const LimitSurface::Impl::Topology& base = surface.impl().topology;
  std::vector<FaceSplit> splits(plan.faces.size());
  tbb::parallel_for(0, static_cast<int>(plan.faces.size()), [&](int f) {
    const SplitPlan::Face& face = plan.faces[f];
    if (face.nu * face.nv == 1) return;
    const OpenSubdiv::Far::ConstIndexArray e = base.faceEdges(f);
    FaceSplit& split = splits[f];
    // Split lines end on existing edge points, so a face splits at most as often as its rates.
    split.nu = std::min(face.nu, floorPow2(std::min(edgeRates[e[0]], edgeRates[e[2]])));
    split.nv = std::min(face.nv, floorPow2(std::min(edgeRates[e[1]], edgeRates[e[3]])));
    if (!split.split()) return;
    askRates(&plan.cells[face.firstCell], face, settings, cap, split);
    // Where every sub-quad asks at least its share of the rate Bfr would give the whole face's
    // interior (e.g. all capped by the texels), splitting would only add transition triangles.
    const int innerU = (edgeRates[e[0]] + edgeRates[e[2]]) / 2;
    const int innerV = (edgeRates[e[1]] + edgeRates[e[3]]) / 2;
    bool pays = false;
    for (size_t q = 0; q < split.askU.size() && !pays; ++q)
      pays = split.askU[q] * split.nu < innerU || split.askV[q] * split.nv < innerV;
    if (!pays) split = FaceSplit{};
  });
  for (const FaceSplit& split : splits) facesSplit += split.split();
  return splits;
}

}  // namespace meso
