// Becker & Max 1993, Figure 2 and eq. (1).
#include "meso/appearance/brdf_table.h"

#include "meso/appearance/table_axis.h"

#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace meso {
namespace {

// Sums f(V, L, N) * mass over the visible normals of each view slice, for every table entry.
// V has azimuth 0 (the histogram's phi axis is phi_N - phi_V) and L azimuth -phi_{V-L}; perNormal
// also gets the slice's view azimuth phi_V about the relief's axes.
template <typename PerNormal>
BrdfTable integrate(const VisibleNormalHistogram& distr, BrdfResolution res, PerNormal perNormal) {
  const HistogramResolution& h = distr.resolution();
  std::vector<float> thetaV(h.thetaV);
  for (int k = 0; k < h.thetaV; ++k) thetaV[k] = distr.thetaV(k);
  const int nPhi = BrdfTable::phiNodes(res, h.phiV), nL = BrdfTable::thetaLNodes(res);
  const float phiLo = h.phiV > 1 ? -kPi : 0.0f;
  std::vector<float> data(BrdfTable::dataSize(res, h.thetaV, h.phiV), 0.0f);
  const size_t half = data.size() / 2;
  // Slices are independent: parallel, and the same bits for any thread count.
  tbb::parallel_for(0, distr.numSlices(), [&](int k) {
    const Vec3 V = polarDirection(distr.sliceThetaV(k), 0.0f);
    const float phiV = h.phiV > 1 ? distr.slicePhiV(k) : 0.0f;
    for (int i = 0; i < nL; ++i)
      for (int j = 0; j < nPhi; ++j) {
        const float tl = kPi * static_cast<float>(i) / static_cast<float>(nL - 1);
        const float pvl = phiLo + kPi * static_cast<float>(j) / static_cast<float>(res.phi - 1);
        const Vec3 L = polarDirection(tl, -pvl);
        double diff = 0.0, spec = 0.0;
        for (int a = 0; a < h.thetaN; ++a)
          for (int b = 0; b < h.phi; ++b) {
            const float m = distr.mass(k, a, b);
            if (m == 0.0f) continue;
            const BrdfTable::Value v = perNormal(V, L, distr.meanNormal(k, a, b), phiV);
            diff += m * v.diffuse;
            spec += m * v.specular;
          }
        const size_t idx = (static_cast<size_t>(k) * nL + i) * nPhi + j;
        data[idx] = static_cast<float>(diff);
        data[half + idx] = static_cast<float>(spec);
      }
  });
  return BrdfTable::fromData(std::move(thetaV), res, std::move(data), h.phiV);
}

}  // namespace

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
                                      const SpecularLobe& lobe) {
  return integrate(distr, res, [&lobe](const Vec3& V, const Vec3& L, const Vec3& nMean, float) {
    Value v;
    v.diffuse = std::max(glm::dot(L, nMean), 0.0f);
    const float len = glm::length(nMean);
    const Vec3 h = V + L;
    const float hl = glm::length(h);
    if (v.diffuse > 0.0f && len > 0.0f && hl > 1e-12f) {  // lit facets only, as shadeLocal
      const float s = lobe.value(std::clamp(glm::dot(h / hl, nMean / len), -1.0f, 1.0f));
      v.specular = std::isfinite(s) ? std::max(s, 0.0f) : 0.0f;
    }
    return v;
  });
}

BrdfTable BrdfTable::fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res,
                                      float phong) {
  return integrate(distr, res, [phong](const Vec3& V, const Vec3& L, const Vec3& nMean, float) {
    // The diffuse term is linear in N: the bin's mean normal (unnormalized) makes it exact.
    Value v;
    v.diffuse = std::max(glm::dot(L, nMean), 0.0f);
    const float len = glm::length(nMean);
    const Vec3 h = V + L;
    const float hl = glm::length(h);
    if (v.diffuse > 0.0f && len > 0.0f && hl > 1e-12f)  // lit facets only, as shadeLocal
      v.specular = std::pow(std::max(glm::dot(h / hl, nMean / len), 0.0f), phong);
    return v;
  });
}

BrdfTable BrdfTable::fromFinerLevel(const VisibleNormalHistogram& distr, BrdfResolution res,
                                    const BrdfTable& finer) {
  return integrate(
      distr, res, [&finer](const Vec3& V, const Vec3& L, const Vec3& nMean, float phiV) {
        const float len = glm::length(nMean);
        if (len == 0.0f) return Value{};
        const Vec3 N = nMean / len;
        // Eq. (1): angles of V and L measured from the bin normal; azimuths in the plane
        // perpendicular to N, against the relief's axes x and y (seen from the view-aligned frame,
        // they are turned by -phi_V; with isotropic tables phi_V is 0 and only phi_{V-L} matters).
        const float c = std::cos(phiV), sn = std::sin(phiV);
        const Vec3 x(c, -sn, 0.0f), y(sn, c, 0.0f);
        const float tv = std::acos(std::clamp(glm::dot(V, N), -1.0f, 1.0f));
        const float tl = std::acos(std::clamp(glm::dot(L, N), -1.0f, 1.0f));
        if (tv >= 0.5f * kPi) return Value{};  // seen from behind the facet
        // A light behind the facet may still light its finer relief: the finer table goes on to
        // theta_L = pi.
        const float pl = std::atan2(glm::dot(L, glm::cross(N, x)), glm::dot(L, glm::cross(y, N)));
        const float pv = std::atan2(glm::dot(V, glm::cross(N, x)), glm::dot(V, glm::cross(y, N)));
        const float pvl = std::fmod(pv - pl + 3.0f * kPi, 2.0f * kPi) - kPi;
        return finer.numPhiV() > 1 ? finer.lookup(tv, pv, tl, pvl)
                                   : finer.lookup(tv, tl, std::abs(pvl));
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

BrdfTable::Value BrdfTable::lookup(float thetaV, float thetaL, float phiVL) const {
  if (phiV_ > 1) return lookup(thetaV, 0.0f, thetaL, phiVL);
  const TableAxis a = locateOnAxis(thetaV, thetaV_.front(), thetaV_.back(), numThetaV());
  const TableAxis b = locateOnAxis(thetaL, 0.0f, kPi, thetaLNodes(res_));
  const float p = std::abs(std::fmod(std::isfinite(phiVL) ? phiVL : 0.0f, 2.0f * kPi));
  const TableAxis c = locateOnAxis(p > kPi ? 2.0f * kPi - p : p, 0.0f, kPi, res_.phi);
  return interpolateTable<Value>(a, TableAxis{}, b, c, layout());
}

BrdfTable::Value BrdfTable::lookup(float thetaV, float phiV, float thetaL, float phiVL) const {
  if (phiV_ == 1) return lookup(thetaV, thetaL, phiVL);
  const TableAxis a = locateOnAxis(thetaV, thetaV_.front(), thetaV_.back(), numThetaV());
  const TableAxis m = locateViewAzimuth(phiV, phiV_);
  const TableAxis b = locateOnAxis(thetaL, 0.0f, kPi, thetaLNodes(res_));
  const TableAxis c = locateOnAxis(wrapAngle(phiVL), -kPi, kPi, nPhi_);
  return interpolateTable<Value>(a, m, b, c, layout());
}

}  // namespace meso
