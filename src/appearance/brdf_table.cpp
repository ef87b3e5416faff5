// Becker & Max 1993, Figure 2 and eq. (1).
#include "meso/appearance/brdf_table.h"

#include "meso/appearance/table_axis.h"

#include "meso/core/math.h"
#include "meso/core/power.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <tbb/parallel_for.h>

namespace meso {
namespace {

// Independent partial sums of sumLocalModel's reductions (QuadratureNormals are padded to a
// multiple of them).
constexpr size_t kLanes = 8;

// Vectors of floats (GCC's and Clang's vector extension) as wide as a register: a block of kLanes
// is one AVX vector, or two of the baseline's. Element-wise operations, each as the scalar one.
// Only functions of this file take or return them (inlined), so their calling convention, which
// differs between the two instruction sets, never crosses a boundary.
#pragma GCC diagnostic ignored "-Wpsabi"
typedef float Floats4 __attribute__((vector_size(4 * sizeof(float))));
typedef float Floats8 __attribute__((vector_size(8 * sizeof(float))));
template <typename V>
constexpr size_t kWidth = sizeof(V) / sizeof(float);
template <typename V>
inline V splat(float v) {
  V r;
  for (size_t l = 0; l < kWidth<V>; ++l) r[l] = v;
  return r;
}
template <typename V>
inline V load(const float* p) {
  V r;
  std::memcpy(&r, p, sizeof r);
  return r;
}

// The visible normals of one view slice as quadrature points: each a group of neighbouring
// histogram bins with their total mass and mass-weighted mean normal (unnormalized, so that the
// diffuse term, linear in N, stays exact), structure of arrays for loops the compiler vectorizes.
// The points run along theta_N within each phi_N column (phi_N outermost), so every block of kLanes
// is a narrow cone of normals: each block's cone (unit axis, and -sin of its half-angle plus a
// margin) is kept for skipping the blocks a light cannot reach.
struct QuadratureNormals {
  std::vector<float> mass, x, y, z, invLength;
  // Per block: the cone's axis, and unlitBelow: every point of the block is unlit where
  // L . axis < unlitBelow (-2: never skipped).
  std::vector<float> axisX, axisY, axisZ, unlitBelow;
  size_t size() const { return mass.size(); }
  size_t blocks() const { return unlitBelow.size(); }
};

// The cone around the points [b, b + kLanes) that have mass, appended to q's blocks: a light at
// more than 90 degrees plus the half-angle from its axis has L.N < 0 on every one of them. The
// margin (1e-3 radian) keeps the test conservative beyond the float rounding of L.N, so that a
// skipped block is one whose points would each have added exactly zero.
void appendCone(QuadratureNormals& q, size_t b) {
  const auto keep = [&q](const glm::dvec3& axis, double unlitBelow) {
    q.axisX.push_back(static_cast<float>(axis.x)), q.axisY.push_back(static_cast<float>(axis.y));
    q.axisZ.push_back(static_cast<float>(axis.z));
    q.unlitBelow.push_back(static_cast<float>(unlitBelow));
  };
  glm::dvec3 sum(0.0);
  for (size_t l = b; l < b + kLanes; ++l)
    if (q.mass[l] > 0.0f)
      sum += glm::dvec3(q.x[l], q.y[l], q.z[l]) * static_cast<double>(q.invLength[l]);
  const double len = glm::length(sum);
  if (!(len > 0.0)) return keep(glm::dvec3(0.0, 0.0, 1.0), -2.0);  // nothing there: never skipped
  const glm::dvec3 axis = sum / len;
  double halfAngle = 0.0;
  for (size_t l = b; l < b + kLanes; ++l)
    if (q.mass[l] > 0.0f) {
      const glm::dvec3 n = glm::dvec3(q.x[l], q.y[l], q.z[l]) * static_cast<double>(q.invLength[l]);
      halfAngle = std::max(halfAngle, std::acos(std::clamp(glm::dot(n, axis), -1.0, 1.0)));
    }
  const double reach = halfAngle + 1e-3;
  if (reach >= 0.5 * std::numbers::pi) return keep(glm::dvec3(0.0, 0.0, 1.0), -2.0);
  keep(axis, -std::sin(reach));
}

QuadratureNormals quadratureNormals(const VisibleNormalHistogram& distr, int k,
                                    const NormalGrouping& g) {
  const HistogramResolution& h = distr.resolution();
  const int gt = std::min(g.thetaNBins(distr.thetaNWidth()), h.thetaN);
  const int gp = std::min(g.phiBins(distr.phiWidth()), h.phi);
  QuadratureNormals q;
  for (int b0 = 0; b0 < h.phi; b0 += gp)
    for (int a0 = 0; a0 < h.thetaN; a0 += gt) {
      double m = 0.0;
      glm::dvec3 n(0.0);
      for (int a = a0; a < std::min(a0 + gt, h.thetaN); ++a)
        for (int b = b0; b < std::min(b0 + gp, h.phi); ++b) {
          const float mb = distr.mass(k, a, b);
          if (mb == 0.0f) continue;
          m += mb;
          n += static_cast<double>(mb) * glm::dvec3(distr.meanNormal(k, a, b));
        }
      if (m == 0.0) continue;
      const Vec3 mean(n / m);
      const float len = glm::length(mean);
      q.mass.push_back(static_cast<float>(m));
      q.x.push_back(mean.x), q.y.push_back(mean.y), q.z.push_back(mean.z);
      q.invLength.push_back(len > 0.0f ? 1.0f / len : 0.0f);
    }
  while (q.size() % kLanes != 0)  // massless padding for the lanes of sumLocalModel
    for (std::vector<float>* v : {&q.mass, &q.x, &q.y, &q.z, &q.invLength}) v->push_back(0.0f);
  for (size_t b = 0; b < q.size(); b += kLanes) appendCone(q, b);
  return q;
}

// The table's light directions in the view-aligned frame of a slice (V at azimuth 0): theta_L node
// i, phi_{V-L} node j at azimuth -phi_{V-L}.
Vec3 lightOfNode(const BrdfResolution& res, int phiV, int i, int j) {
  const int nL = BrdfTable::thetaLNodes(res);
  const float tl = kPi * static_cast<float>(i) / static_cast<float>(nL - 1);
  const float pvl =
      (phiV > 1 ? -kPi : 0.0f) + kPi * static_cast<float>(j) / static_cast<float>(res.phi - 1);
  return polarDirection(tl, -pvl);
}

// Fills every (theta_V, phi_V) slice of a table with perSlice(k, V, sums), which writes the
// slice's nL * nPhi diffuse values to sums and the specular ones after them. Slices are
// independent: parallel, and the same bits for any thread count.
template <typename PerSlice>
BrdfTable integrate(const VisibleNormalHistogram& distr, BrdfResolution res, ViewRows rows,
                    PerSlice perSlice) {
  const HistogramResolution& h = distr.resolution();
  std::vector<float> thetaV(h.thetaV);
  for (int k = 0; k < h.thetaV; ++k) thetaV[k] = distr.thetaV(k);
  const size_t perView =
      static_cast<size_t>(BrdfTable::phiNodes(res, h.phiV)) * BrdfTable::thetaLNodes(res);
  std::vector<float> data(BrdfTable::dataSize(res, h.thetaV, h.phiV), 0.0f);
  const size_t half = data.size() / 2;
  tbb::parallel_for(0, distr.numSlices(), [&](int k) {
    if (!rows.contains(k / h.phiV)) return;
    std::vector<double> sums(2 * perView, 0.0);
    perSlice(k, polarDirection(distr.sliceThetaV(k), 0.0f), sums);
    for (size_t e = 0; e < perView; ++e) {
      data[k * perView + e] = static_cast<float>(sums[e]);
      data[half + k * perView + e] = static_cast<float>(sums[perView + e]);
    }
  });
  BrdfTable t = BrdfTable::fromData(std::move(thetaV), res, std::move(data), h.phiV);
  t.setViewRows(rows);
  return t;
}

// Figure 2's first branch over the quadrature normals: sums[node] gets sum m (L.N)+ and
// sums[perView + node] sum m lobe(H.N) over lit facets (as shadeLocal). lobeOf turns the clamped
// cosines of one block (n vectors), in place, into the lobe's values. Blocks whose cone
// the light cannot reach are left out: each of their points would add exactly +-0 to its lane, so
// the sums are the same bits as over every point (on a rough relief about half of the pairs are
// unlit, most of them in blocks left out). A block is one or two vectors (kLanes floats): its
// terms stay in registers, and lane l of the sums takes the points l, l + kLanes, ... in order
// (independent lanes: a reduction the compiler vectorizes without reordering any one sum, so the
// same bits on every machine).
template <typename V, typename LobeOf>
inline void sumLocalModel(const QuadratureNormals& q, const BrdfResolution& res, int phiV,
                          const Vec3& V3, LobeOf lobeOf, std::vector<double>& sums) {
  constexpr size_t kW = kWidth<V>, kSub = kLanes / kW;  // vectors per block
  const int nL = BrdfTable::thetaLNodes(res), nPhi = BrdfTable::phiNodes(res, phiV);
  const size_t perView = static_cast<size_t>(nL) * nPhi, blocks = q.blocks();
  std::vector<float> reach(blocks);
  std::vector<uint32_t> reached(blocks);
  const float *ax = q.axisX.data(), *ay = q.axisY.data(), *az = q.axisZ.data();
  const float* below = q.unlitBelow.data();
  const float *x = q.x.data(), *y = q.y.data(), *z = q.z.data();
  const float *inv = q.invLength.data(), *mass = q.mass.data();  // padded to whole blocks
  const V zero = splat<V>(0.0f), one = splat<V>(1.0f);
  for (int i = 0; i < nL; ++i)
    for (int j = 0; j < nPhi; ++j) {
      const Vec3 L = lightOfNode(res, phiV, i, j);
      const Vec3 h = V3 + L;
      const float hl = glm::length(h);
      const Vec3 H = hl > 1e-12f ? h / hl : Vec3(0.0f);
      const float lx = L.x, ly = L.y, lz = L.z;
      for (size_t kb = 0; kb < blocks; ++kb)  // >= 0 where the light may reach the block
        reach[kb] = lx * ax[kb] + ly * ay[kb] + lz * az[kb] - below[kb];
      size_t n = 0;  // the reached blocks, listed without a branch per block
      for (size_t kb = 0; kb < blocks; ++kb) {
        reached[n] = static_cast<uint32_t>(kb);
        n += reach[kb] >= 0.0f ? 1 : 0;
      }
      const V lxv = splat<V>(lx), lyv = splat<V>(ly), lzv = splat<V>(lz);
      const V hxv = splat<V>(H.x), hyv = splat<V>(H.y), hzv = splat<V>(H.z);
      V diff[kSub], spec[kSub];
      for (size_t u = 0; u < kSub; ++u) diff[u] = zero, spec[u] = zero;
      for (size_t r = 0; r < n; ++r) {
        const size_t p0 = static_cast<size_t>(reached[r]) * kLanes;
        V d[kSub], c[kSub];
        for (size_t u = 0; u < kSub; ++u) {
          const size_t p = p0 + u * kW;
          const V xv = load<V>(x + p), yv = load<V>(y + p), zv = load<V>(z + p);
          const V lDotN = lxv * xv + lyv * yv + lzv * zv;
          const V cosHN = (hxv * xv + hyv * yv + hzv * zv) * load<V>(inv + p);
          const V lit = lDotN > zero ? one : zero;
          const V atLeast0 = cosHN < zero ? zero : cosHN;  // std::max(cosHN, 0), NaN kept
          d[u] = lit * lDotN;
          c[u] = lit * (one < atLeast0 ? one : atLeast0);  // std::min(.., 1)
        }
        lobeOf(c, kSub);
        for (size_t u = 0; u < kSub; ++u) {
          const V m = load<V>(mass + p0 + u * kW);
          diff[u] += m * d[u], spec[u] += m * c[u];
        }
      }
      double dSum = 0.0, sSum = 0.0;  // lanes 0 to kLanes - 1 in order
      for (size_t u = 0; u < kSub; ++u)
        for (size_t l = 0; l < kW; ++l) dSum += diff[u][l], sSum += spec[u][l];
      sums[static_cast<size_t>(i) * nPhi + j] = dSum;
      sums[perView + static_cast<size_t>(i) * nPhi + j] = sSum;
    }
}

// c^e on the n <= kLanes / width vectors of a block, as raiseToPower takes it (the same float
// operations per value).
struct PhongLobe {
  explicit PhongLobe(float e)
      : e(e), whole(isWholePower(e)), bits(whole ? static_cast<unsigned>(e) : 0u) {}
  float e;
  bool whole;
  unsigned bits;
  template <typename V>
  void operator()(V* c, size_t n) const {
    if (!whole) {
      for (size_t g = 0; g < n; ++g)
        for (size_t l = 0; l < kWidth<V>; ++l) c[g][l] = std::pow(c[g][l], e);
      return;
    }
    V acc[kLanes / kWidth<V>];  // 1 * c is exactly c: the same bits as from the first power taken
    for (size_t g = 0; g < n; ++g) acc[g] = splat<V>(1.0f);
    for (unsigned b = bits;;) {
      if (b & 1u)
        for (size_t g = 0; g < n; ++g) acc[g] *= c[g];
      b >>= 1;
      if (b == 0) break;
      for (size_t g = 0; g < n; ++g) c[g] *= c[g];
    }
    for (size_t g = 0; g < n; ++g) c[g] = acc[g];
  }
};

// The Phong integration of one view slice, compiled twice: for the baseline x86-64 vectors and,
// where the CPU has them, for AVX2's (twice the lanes). Both do the same float operations in the
// same order (no fused multiply-add), so the sums are the same bits
// (`BrdfTable.WideAndBaselineVectorsGiveTheSameBits`).
__attribute__((flatten)) void sumPhongBaseline(const QuadratureNormals& q,
                                               const BrdfResolution& res, int phiV, const Vec3& V,
                                               float phong, std::vector<double>& sums) {
  sumLocalModel<Floats4>(q, res, phiV, V, PhongLobe{phong}, sums);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"), flatten)) void sumPhongAvx2(const QuadratureNormals& q,
                                                           const BrdfResolution& res, int phiV,
                                                           const Vec3& V, float phong,
                                                           std::vector<double>& sums) {
  sumLocalModel<Floats8>(q, res, phiV, V, PhongLobe{phong}, sums);
}
#endif

std::atomic<BrdfVectors> gVectors{BrdfVectors::best};

bool cpuHasAvx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

void sumPhong(const QuadratureNormals& q, const BrdfResolution& res, int phiV, const Vec3& V,
              float phong, std::vector<double>& sums) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (cpuHasAvx2() && gVectors.load(std::memory_order_relaxed) == BrdfVectors::best)
    return sumPhongAvx2(q, res, phiV, V, phong, sums);
#endif
  sumPhongBaseline(q, res, phiV, V, phong, sums);
}

// Whole bins within a group's width (at least one).
int binsWithin(float groupWidth, float binWidth) {
  const float n = groupWidth / binWidth;
  return std::isfinite(n) && n >= 1.0f ? static_cast<int>(std::floor(n + 1e-3f)) : 1;
}

}  // namespace

void setBrdfVectors(BrdfVectors v) { gVectors.store(v); }
bool brdfHasWiderVectors() { return cpuHasAvx2(); }

int NormalGrouping::thetaNBins(float width) const { return binsWithin(thetaN, width); }
int NormalGrouping::phiBins(float width) const { return binsWithin(phi, width); }

BrdfTable BrdfTable::fromData(std::vector<float> thetaV, BrdfResolution res,
                              std::vector<float> data, int phiV) {
  BrdfTable t;
  t.thetaV_ = std::move(thetaV);
  t.res_ = res;
  t.phiV_ = std::max(phiV, 1);
  t.nPhi_ = phiNodes(res, t.phiV_);
  t.data_ = std::move(data);
  return t;
}

BrdfTable BrdfTable::fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res,
                                      const SpecularLobe& lobe, ViewRows rows) {
  const int phiV = distr.resolution().phiV;
  return integrate(distr, res, rows, [&](int k, const Vec3& V, std::vector<double>& sums) {
    const auto lobeOf = [&lobe](Floats4* c, size_t n) {
      for (size_t g = 0; g < n; ++g)
        for (size_t l = 0; l < kWidth<Floats4>; ++l) {
          if (c[g][l] == 0.0f) continue;  // unlit, or facing away from H: no highlight, as (H.N)+^n
          const float s = lobe.value(c[g][l]);
          c[g][l] = std::isfinite(s) ? std::max(s, 0.0f) : 0.0f;
        }
    };
    sumLocalModel<Floats4>(quadratureNormals(distr, k, res.finest), res, phiV, V, lobeOf, sums);
  });
}

BrdfTable BrdfTable::fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res,
                                      float phong, ViewRows rows) {
  const int phiV = distr.resolution().phiV;
  return integrate(distr, res, rows, [&](int k, const Vec3& V, std::vector<double>& sums) {
    sumPhong(quadratureNormals(distr, k, res.finest), res, phiV, V, phong, sums);
  });
}

BrdfTable BrdfTable::fromFinerLevel(const VisibleNormalHistogram& distr, BrdfResolution res,
                                    const BrdfTable& finer, ViewRows rows) {
  const int phiV = distr.resolution().phiV;
  const int nL = thetaLNodes(res), nPhi = phiNodes(res, phiV);
  const size_t perView = static_cast<size_t>(nL) * nPhi;
  std::vector<Vec3> lights(perView);
  for (int i = 0; i < nL; ++i)
    for (int j = 0; j < nPhi; ++j)
      lights[static_cast<size_t>(i) * nPhi + j] = lightOfNode(res, phiV, i, j);
  return integrate(distr, res, rows, [&](int k, const Vec3& V, std::vector<double>& sums) {
    const QuadratureNormals q = quadratureNormals(distr, k, res.coarser);
    // Eq. (1): angles of V and L measured from the quadrature normal; azimuths in the plane
    // perpendicular to N, against the relief's axes x and y (seen from the view-aligned frame,
    // they are turned by -phi_V; with isotropic tables phi_V is 0 and only phi_{V-L} matters).
    const float phiVSlice = phiV > 1 ? distr.slicePhiV(k) : 0.0f;
    const float c = std::cos(phiVSlice), sn = std::sin(phiVSlice);
    const Vec3 x(c, -sn, 0.0f), y(sn, c, 0.0f);
    for (size_t b = 0; b < q.size(); ++b) {
      if (q.invLength[b] == 0.0f) continue;
      const Vec3 N = Vec3(q.x[b], q.y[b], q.z[b]) * q.invLength[b];
      const float tv = fastAcos(glm::dot(V, N));
      if (tv >= 0.5f * kPi) continue;  // seen from behind the facet
      const Vec3 ex = glm::cross(N, x), ey = glm::cross(y, N);
      const float pv = fastAtan2(glm::dot(V, ex), glm::dot(V, ey));
      const ViewAxes view = finer.locateView(tv, pv);
      const double m = q.mass[b];
      for (size_t e = 0; e < perView; ++e) {
        const Vec3& L = lights[e];
        // A light behind the facet may still light its finer relief: the finer table goes on
        // to theta_L = pi.
        const float tl = fastAcos(glm::dot(L, N));
        const float pl = fastAtan2(glm::dot(L, ex), glm::dot(L, ey));
        const float pvl = wrapAngle(pv - pl);
        const Value v = finer.lookup(view, tl, pvl);
        sums[e] += m * v.diffuse;
        sums[perView + e] += m * v.specular;
      }
    }
  });
}

float BrdfTable::thetaL(int i) const {
  return kPi * static_cast<float>(i) / static_cast<float>(thetaLNodes(res_) - 1);
}
float BrdfTable::phi(int j) const {
  return (phiV_ > 1 ? -kPi : 0.0f) + kPi * static_cast<float>(j) / static_cast<float>(res_.phi - 1);
}

BrdfTable::Value BrdfTable::entry(int k, int i, int j) const {
  return {data_[index(k, i, j)], data_[data_.size() / 2 + index(k, i, j)]};
}

BrdfTable::ViewAxes BrdfTable::locateView(float thetaV, float phiV) const {
  return {locateOnAxis(thetaV, thetaV_.front(), thetaV_.back(), numThetaV(), rows_),
          locateViewAzimuth(phiV, phiV_)};
}

BrdfTable::Value BrdfTable::lookup(const ViewAxes& view, float thetaL, float phiVL) const {
  const TableAxis b = locateOnAxis(thetaL, 0.0f, kPi, thetaLNodes(res_));
  TableAxis c;
  if (phiV_ > 1) {
    c = locateOnAxis(wrapAngle(phiVL), -kPi, kPi, nPhi_);
  } else {  // isotropic: |phi_{V-L}| over [0, pi]
    const float p = std::abs(std::fmod(std::isfinite(phiVL) ? phiVL : 0.0f, 2.0f * kPi));
    c = locateOnAxis(p > kPi ? 2.0f * kPi - p : p, 0.0f, kPi, res_.phi);
  }
  return interpolateTable<Value>(view.thetaV, view.phiV, b, c, layout());
}

BrdfTable::Value BrdfTable::lookup(float thetaV, float thetaL, float phiVL) const {
  return lookup(locateView(thetaV, 0.0f), thetaL, phiVL);
}

BrdfTable::Value BrdfTable::lookup(float thetaV, float phiV, float thetaL, float phiVL) const {
  return lookup(locateView(thetaV, phiV), thetaL, phiVL);
}

}  // namespace meso
