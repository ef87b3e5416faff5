// Becker & Max 1993, section 4.2 (shadows): the relief's self-shadowing factor, traced with shadow
// rays from the visible hits of the periodic tile (DESIGN.md section 6).
#include "meso/appearance/shadowing_table.h"

#include "meso/appearance/class_map.h"
#include "meso/appearance/table_axis.h"

#include "meso/core/power.h"
#include "meso/core/rng.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <span>

namespace meso {
namespace {

// A surface-frame direction into tile coordinates through the shape (class_map.h).
Vec3 toTile(const Vec3& w, const MetricShape& s) { return ClassMap{s}.toTile(w); }

struct Hit {
  Vec3 p;  // tile coordinates, just off the surface
  Vec3 n;  // unit Blinn normal in the surface frame
};

// The visible hits of one slice, each lifted off the relief along its tile normal.
std::vector<std::pair<Hit, float>> visibleHits(const PeriodicRelief& relief,
                                               const PeriodicTile& tile, const MetricShape& shape,
                                               float thetaV, float phiLo, float phiWidth,
                                               int azimuths, int rays, Rng& rng) {
  std::vector<std::pair<Hit, float>> hits;  // with the view azimuth they were seen from
  hits.reserve(static_cast<size_t>(rays));
  // Jittered strata over the tile per azimuth: the lit fraction is an area integral, and strata
  // converge much faster than independent origins on its smooth shadow boundaries.
  const int perAzimuth = std::max(rays / std::max(azimuths, 1), 1);
  const int side = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(perAzimuth))));
  for (int a = 0; a < azimuths; ++a)
    for (int r = 0; r < side * side; ++r) {
      const float phiV =
          phiLo + phiWidth * (static_cast<float>(a) + 0.5f) / static_cast<float>(azimuths);
      const Vec3 eye = toTile(polarDirection(thetaV, phiV), shape);
      const Vec2 xy((static_cast<float>(r % side) + rng.uniform()) / side,
                    (static_cast<float>(r / side) + rng.uniform()) / side);
      Vec3 p;
      if (!tile.traceHit(Vec3(xy, tile.zMax() + 1e-3f), -eye, p)) continue;
      const Vec2 g = relief.gradient(p.x, p.y);
      const Vec3 nTile = glm::normalize(Vec3(-g.x, -g.y, 1.0f));
      // Off the surface by 1e-4 tile units along its normal: the tile's float rounding is ~1e-7.
      hits.push_back(
          {{p + 1e-4f * nTile, ClassMap{shape}.normalFromTile(Vec3(-g.x, -g.y, 1.0f))}, phiV});
    }
  return hits;
}

// The light's sums at one (theta_L, phi_{V-L}) node over the visible hits of a slice.
struct NodeSums {
  double d = 0.0, dLit = 0.0, s = 0.0, sLit = 0.0;
};

// Adds every visible hit's reflected light at the nodes thetaL (ascending, in (0, pi/2]) x phiVL
// into sums[i * phiVL.size() + j], lit or not. A hit's lights at one azimuth share their
// horizontal tile direction: one horizon march (PeriodicTile::horizon) decides all of them,
// unless withShadowRays asks for a ray per node (the reference).
void sumSlice(const std::vector<std::pair<Hit, float>>& hits, const PeriodicTile& tile,
              const MetricShape& shape, float thetaV, const std::vector<float>& thetaL,
              const std::vector<float>& phiVL, float phong, bool withShadowRays,
              std::vector<NodeSums>& sums) {
  const int nL = static_cast<int>(thetaL.size()), nPhi = static_cast<int>(phiVL.size());
  std::vector<float> sinL(nL), cosL(nL), cotL(nL), slopes(nL), lDotN(nL), ws(nL), lvB(nPhi);
  std::vector<int> node(nL);
  for (int i = 0; i < nL; ++i)
    sinL[i] = std::sin(thetaL[i]), cosL[i] = std::cos(thetaL[i]), cotL[i] = cosL[i] / sinL[i];
  const float sinV = std::sin(thetaV), cosV = std::cos(thetaV);
  for (int j = 0; j < nPhi; ++j) lvB[j] = sinV * std::cos(phiVL[j]);  // L.V = sinL B + cosL cosV
  for (const auto& [hit, phiV] : hits) {
    const Vec3& n = hit.n;
    const float vDotN = glm::dot(polarDirection(thetaV, phiV), n);
    for (int j = 0; j < nPhi; ++j) {
      const float phiL = phiV - phiVL[j], cosPhi = std::cos(phiL), sinPhi = std::sin(phiL);
      const float lnA = cosPhi * n.x + sinPhi * n.y;  // L.n = sinL lnA + cosL n.z
      // toTile is linear in the horizontal part: every theta_L has this tile direction.
      const Vec2 h = ClassMap{shape}.horizontalToTile({cosPhi, sinPhi});
      const float hLength = glm::length(h);
      for (int i = 0; i < nL; ++i) {
        const float lDotV = sinL[i] * lvB[j] + cosL[i] * cosV;
        lDotN[i] = sinL[i] * lnA + cosL[i] * n.z;
        ws[i] = std::max((lDotN[i] + vDotN) / std::sqrt(std::max(2.0f + 2.0f * lDotV, 1e-30f)),
                         0.0f);  // H.n, raised to the highlight below
      }
      raiseToPower(ws, phong);
      int count = 0;
      for (int i = nL - 1; i >= 0; --i) {  // descending theta_L: ascending slopes
        const float d = std::max(lDotN[i], 0.0f);
        if (d <= 0.0f && !(ws[i] > 1e-6f)) continue;  // reflects nothing: lit or not is moot
        slopes[count] = cotL[i] / hLength;
        node[count] = i;
        ++count;
      }
      if (count == 0) continue;
      const float horizon =
          withShadowRays
              ? 0.0f
              : tile.horizon(hit.p, h / hLength, std::span<const float>(slopes.data(), count),
                             kShadowMaxTiles);
      for (int q = 0; q < count; ++q) {
        const int i = node[q];
        const bool lit =
            withShadowRays
                ? !tile.occluded(hit.p,
                                 toTile({sinL[i] * cosPhi, sinL[i] * sinPhi, cosL[i]}, shape),
                                 kShadowMaxTiles)
                : slopes[q] > horizon;
        const float d = std::max(lDotN[i], 0.0f);
        NodeSums& sum = sums[static_cast<size_t>(i) * nPhi + j];
        sum.d += d, sum.s += ws[i];
        if (lit) sum.dLit += d, sum.sLit += ws[i];
      }
    }
  }
}

}  // namespace

ShadowingTable ShadowingTable::trace(const PeriodicRelief& relief, const PeriodicTile& tile,
                                     const VisibleNormalHistogram& layout,
                                     const HistogramSettings& hs, ShadowingResolution res,
                                     float phong, uint64_t seed, ViewRows rows) {
  return traceWith(relief, tile, layout, hs, res, phong, seed, false, rows);
}

ShadowingTable ShadowingTable::traceWithShadowRays(
    const PeriodicRelief& relief, const PeriodicTile& tile, const VisibleNormalHistogram& layout,
    const HistogramSettings& hs, ShadowingResolution res, float phong, uint64_t seed) {
  return traceWith(relief, tile, layout, hs, res, phong, seed, true, {});
}

ShadowingTable ShadowingTable::traceWith(const PeriodicRelief& relief, const PeriodicTile& tile,
                                         const VisibleNormalHistogram& layout,
                                         const HistogramSettings& hs, ShadowingResolution res,
                                         float phong, uint64_t seed, bool withShadowRays,
                                         ViewRows rows) {
  ShadowingTable t = onNodes(layout, res);
  t.setViewRows(rows);
  const int slices = t.numThetaV() * t.phiV_;
  const size_t half = t.data_.size() / 2;
  std::vector<float> phiVL(t.nPhi_);
  for (int j = 0; j < t.nPhi_; ++j) phiVL[j] = t.phi(j);
  tbb::parallel_for(0, slices, [&](int k) {
    if (!t.rows_.contains(k / t.phiV_)) return;
    Rng rng(seed, static_cast<uint64_t>(k));
    const float phiWidth = 2.0f * kPi / static_cast<float>(t.phiV_);
    const float phiLo = t.phiV_ > 1 ? layout.phiVCentre(k % t.phiV_) - 0.5f * phiWidth : 0.0f;
    const float thetaV = t.thetaV_[k / t.phiV_];
    const int azimuths = t.phiV_ > 1 ? res.azimuthsPerSlice : 8 * res.azimuthsPerSlice;
    // An isotropic table has one slice per theta_V: it gets the hits of 32 azimuth slices (as many
    // as twice the default 16 view-azimuth slices; at 8, the steep relief was 1.1% off by noise).
    const int rays = t.phiV_ > 1 ? res.raysPerSlice : 32 * res.raysPerSlice;
    const auto hits =
        visibleHits(relief, tile, hs.shape, thetaV, phiLo, phiWidth, azimuths, rays, rng);
    // The distinct lights: theta_L = 0 is never shadowed (a height field), and nodes clamped at
    // the horizon repeat the last one.
    std::vector<float> thetaL;
    std::vector<int> light(t.numDelta(), -1);
    for (int i = 0; i < t.numDelta(); ++i) {
      const float tl = std::clamp(thetaV + t.delta(i), 0.0f, 0.5f * kPi);
      if (tl <= 0.0f) continue;
      if (thetaL.empty() || tl != thetaL.back()) thetaL.push_back(tl);
      light[i] = static_cast<int>(thetaL.size()) - 1;
    }
    std::vector<NodeSums> sums(thetaL.size() * t.nPhi_);
    sumSlice(hits, tile, hs.shape, thetaV, thetaL, phiVL, phong, withShadowRays, sums);
    for (int i = 0; i < t.numDelta(); ++i)
      for (int j = 0; light[i] >= 0 && j < t.nPhi_; ++j) {
        const NodeSums& sum = sums[static_cast<size_t>(light[i]) * t.nPhi_ + j];
        const size_t idx = t.index(k, i, j);
        t.data_[idx] = sum.d > 0.0 ? static_cast<float>(sum.dLit / sum.d) : 1.0f;
        t.data_[half + idx] = sum.s > 0.0 ? static_cast<float>(sum.sLit / sum.s) : 1.0f;
      }
  });
  return t;
}

ShadowingTable ShadowingTable::onNodes(const VisibleNormalHistogram& layout,
                                       ShadowingResolution res) {
  ShadowingTable t;
  const HistogramResolution& h = layout.resolution();
  t.res_ = res;
  t.phiV_ = std::max(h.phiV, 1);
  t.nPhi_ = phiNodes(res, t.phiV_);
  const int nV = (h.thetaV - 1) * std::max(res.thetaVRefine, 1) + 1;
  t.thetaV_.resize(nV);
  for (int k = 0; k < nV; ++k)
    t.thetaV_[k] = layout.thetaVMax() * static_cast<float>(k) / static_cast<float>(nV - 1);
  t.data_.assign(2 * static_cast<size_t>(nV) * t.phiV_ * t.numDelta() * t.nPhi_, 1.0f);
  return t;
}

ShadowingTable ShadowingTable::tabulate(const VisibleNormalHistogram& layout,
                                        ShadowingResolution res, const NodeFunction& f,
                                        ViewRows rows) {
  ShadowingTable t = onNodes(layout, res);
  t.setViewRows(rows);
  const size_t half = t.data_.size() / 2;
  tbb::parallel_for(0, t.numThetaV() * t.phiV_, [&](int k) {
    if (!t.rows_.contains(k / t.phiV_)) return;
    const float thetaV = t.thetaV_[k / t.phiV_];
    const float phiV = t.phiV_ > 1 ? layout.phiVCentre(k % t.phiV_) : 0.0f;
    for (int i = 0; i < t.numDelta(); ++i) {
      // As trace(): a light at or below theta_L = 0 is never shadowed.
      const float thetaL = std::clamp(thetaV + t.delta(i), 0.0f, 0.5f * kPi);
      if (thetaL <= 0.0f) continue;
      for (int j = 0; j < t.nPhi_; ++j) {
        const Value v = f(thetaV, phiV, thetaL, t.phi(j));
        t.data_[t.index(k, i, j)] = std::clamp(v.diffuse, 0.0f, 1.0f);
        t.data_[half + t.index(k, i, j)] = std::clamp(v.specular, 0.0f, 1.0f);
      }
    }
  });
  return t;
}

float ShadowingTable::delta(int i) const {
  return -0.5f * kPi + 0.5f * kPi * static_cast<float>(i) / static_cast<float>(res_.thetaL - 1);
}
float ShadowingTable::phi(int j) const {
  return (phiV_ > 1 ? -kPi : 0.0f) + kPi * static_cast<float>(j) / static_cast<float>(res_.phi - 1);
}

ShadowingTable::Value ShadowingTable::entry(int slice, int i, int j) const {
  return {data_[index(slice, i, j)], data_[data_.size() / 2 + index(slice, i, j)]};
}

ShadowingTable::Value ShadowingTable::lookup(float thetaV, float phiV, float thetaL,
                                             float phiVL) const {
  if (data_.empty()) return {};
  const TableAxis a = locateOnAxis(thetaV, thetaV_.front(), thetaV_.back(), numThetaV(), rows_);
  const TableAxis m = locateViewAzimuth(phiV, phiV_);
  // The same offset theta_L - theta_V in both theta_V slices: along the hot-spot ridge.
  const int n = numThetaV();
  const int first = rows_.all() ? 0 : std::clamp(rows_.first, 0, n - 1);
  const int last = rows_.all() ? n - 1 : std::clamp(rows_.last, first, n - 1);
  const float tv = std::clamp(std::isfinite(thetaV) ? thetaV : 0.0f, thetaV_[first], thetaV_[last]);
  const TableAxis b = locateOnAxis(thetaL - tv, -0.5f * kPi, 0.5f * kPi, numDelta());
  const float p = wrapAngle(phiVL);
  const TableAxis c =
      phiV_ > 1 ? locateOnAxis(p, -kPi, kPi, nPhi_) : locateOnAxis(std::abs(p), 0.0f, kPi, nPhi_);
  return interpolateTable<Value>(a, m, b, c, layout());
}

std::vector<float> ShadowingTable::toData() const {
  std::vector<float> out;
  out.push_back(static_cast<float>(thetaV_.size()));
  out.push_back(static_cast<float>(phiV_));
  out.insert(out.end(), thetaV_.begin(), thetaV_.end());
  out.insert(out.end(), data_.begin(), data_.end());
  return out;
}

bool ShadowingTable::fromData(const std::vector<float>& data, ShadowingResolution res,
                              ShadowingTable& out) {
  if (data.size() < 2) return false;
  const int nThetaV = static_cast<int>(data[0]), phiV = static_cast<int>(data[1]);
  if (nThetaV < 2 || phiV < 1 || nThetaV > 4096 || phiV > 4096) return false;
  const size_t n =
      2 * static_cast<size_t>(nThetaV) * phiV * (2 * res.thetaL - 1) * phiNodes(res, phiV);
  if (data.size() != 2 + nThetaV + n) return false;
  ShadowingTable t;
  t.res_ = res;
  t.phiV_ = phiV;
  t.nPhi_ = phiNodes(res, phiV);
  t.thetaV_.assign(data.begin() + 2, data.begin() + 2 + nThetaV);
  t.data_.assign(data.begin() + 2 + nThetaV, data.end());
  for (float v : t.data_)
    if (!(v >= 0.0f && v <= 1.0f)) return false;
  out = std::move(t);
  return true;
}

}  // namespace meso
