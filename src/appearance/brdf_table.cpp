// Becker & Max 1993, Figure 2 and eq. (1).
#include "meso/appearance/brdf_table.h"

#include "meso/core/math.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace meso {
namespace {

struct Axis {
  int i0;
  int i1;
  float w;
};

Axis locate(float x, float lo, float hi, int n) {
  float s = std::isfinite(x) ? (x - lo) / (hi - lo) * static_cast<float>(n - 1) : 0.0f;
  s = std::clamp(s, 0.0f, static_cast<float>(n - 1));
  const int i0 = std::min(static_cast<int>(s), std::max(n - 2, 0));
  return {i0, std::min(i0 + 1, n - 1), s - static_cast<float>(i0)};
}

Vec3 direction(float theta, float phi) {
  const float s = std::sin(theta);
  return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

// Sums f(V, L, N) * mass over the visible normals of each view slice, for every table entry.
// V has azimuth 0 (the histogram's phi axis is phi_N - phi_V) and L azimuth -phi_{V-L}.
template <typename PerNormal>
BrdfTable integrate(const VisibleNormalHistogram& distr, BrdfResolution res, PerNormal perNormal) {
  const HistogramResolution& h = distr.resolution();
  std::vector<float> thetaV(h.thetaV);
  for (int k = 0; k < h.thetaV; ++k) thetaV[k] = distr.thetaV(k);
  std::vector<float> data(2 * static_cast<size_t>(h.thetaV) * res.thetaL * res.phi, 0.0f);
  const size_t half = data.size() / 2;
  // Slices are independent: parallel, and the same bits for any thread count.
  tbb::parallel_for(0, h.thetaV, [&](int k) {
    const Vec3 V = direction(thetaV[k], 0.0f);
    for (int i = 0; i < res.thetaL; ++i)
      for (int j = 0; j < res.phi; ++j) {
        const float tl = 0.5f * kPi * static_cast<float>(i) / static_cast<float>(res.thetaL - 1);
        const float pvl = kPi * static_cast<float>(j) / static_cast<float>(res.phi - 1);
        const Vec3 L = direction(tl, -pvl);
        double diff = 0.0, spec = 0.0;
        for (int a = 0; a < h.thetaN; ++a)
          for (int b = 0; b < h.phi; ++b) {
            const float m = distr.mass(k, a, b);
            if (m == 0.0f) continue;
            const BrdfTable::Value v = perNormal(V, L, distr.meanNormal(k, a, b));
            diff += m * v.diffuse;
            spec += m * v.specular;
          }
        const size_t idx = (static_cast<size_t>(k) * res.thetaL + i) * res.phi + j;
        data[idx] = static_cast<float>(diff);
        data[half + idx] = static_cast<float>(spec);
      }
  });
  return BrdfTable::fromData(std::move(thetaV), res, std::move(data));
}

}  // namespace

BrdfTable BrdfTable::fromData(std::vector<float> thetaV, BrdfResolution res, std::vector<float> data) {
  BrdfTable t;
  t.thetaV_ = std::move(thetaV);
  t.res_ = res;
  t.data_ = std::move(data);
  return t;
}

BrdfTable BrdfTable::fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res,
                                      const SpecularLobe& lobe) {
  return integrate(distr, res, [&lobe](const Vec3& V, const Vec3& L, const Vec3& nMean) {
    Value v;
    v.diffuse = std::max(glm::dot(L, nMean), 0.0f);
    const float len = glm::length(nMean);
    const Vec3 h = V + L;
    const float hl = glm::length(h);
    if (len > 0.0f && hl > 1e-12f) {
      const float s = lobe.value(std::clamp(glm::dot(h / hl, nMean / len), -1.0f, 1.0f));
      v.specular = std::isfinite(s) ? std::max(s, 0.0f) : 0.0f;
    }
    return v;
  });
}

BrdfTable BrdfTable::fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res, float phong) {
  return integrate(distr, res, [phong](const Vec3& V, const Vec3& L, const Vec3& nMean) {
    // The diffuse term is linear in N: the bin's mean normal (unnormalized) makes it exact.
    Value v;
    v.diffuse = std::max(glm::dot(L, nMean), 0.0f);
    const float len = glm::length(nMean);
    const Vec3 h = V + L;
    const float hl = glm::length(h);
    if (len > 0.0f && hl > 1e-12f) v.specular = std::pow(std::max(glm::dot(h / hl, nMean / len), 0.0f), phong);
    return v;
  });
}

BrdfTable BrdfTable::fromFinerLevel(const VisibleNormalHistogram& distr, BrdfResolution res,
                                    const BrdfTable& finer) {
  return integrate(distr, res, [&finer](const Vec3& V, const Vec3& L, const Vec3& nMean) {
    const float len = glm::length(nMean);
    if (len == 0.0f) return Value{};
    const Vec3 N = nMean / len;
    // Eq. (1): angles of V and L measured from the bin normal; azimuths in the plane perpendicular
    // to N, against the table axes x and y.
    const Vec3 x(1.0f, 0.0f, 0.0f), y(0.0f, 1.0f, 0.0f);
    const float tv = std::acos(std::clamp(glm::dot(V, N), -1.0f, 1.0f));
    const float tl = std::acos(std::clamp(glm::dot(L, N), -1.0f, 1.0f));
    if (tl >= 0.5f * kPi || tv >= 0.5f * kPi) return Value{};  // lit or seen from behind the facet
    const float pl = std::atan2(glm::dot(L, glm::cross(N, x)), glm::dot(L, glm::cross(y, N)));
    const float pv = std::atan2(glm::dot(V, glm::cross(N, x)), glm::dot(V, glm::cross(y, N)));
    const float pvl = std::fmod(pv - pl + 3.0f * kPi, 2.0f * kPi) - kPi;
    return finer.lookup(tv, tl, std::abs(pvl));
  });
}

float BrdfTable::thetaL(int i) const { return 0.5f * kPi * static_cast<float>(i) / static_cast<float>(res_.thetaL - 1); }
float BrdfTable::phi(int j) const { return kPi * static_cast<float>(j) / static_cast<float>(res_.phi - 1); }

BrdfTable::Value BrdfTable::entry(int k, int i, int j) const {
  return {data_[index(k, i, j)], data_[data_.size() / 2 + index(k, i, j)]};
}

BrdfTable::Value BrdfTable::lookup(float thetaV, float thetaL, float phiVL) const {
  const Axis a = locate(thetaV, thetaV_.front(), thetaV_.back(), numThetaV());
  const Axis b = locate(thetaL, 0.0f, 0.5f * kPi, res_.thetaL);
  const float p = std::abs(std::fmod(std::isfinite(phiVL) ? phiVL : 0.0f, 2.0f * kPi));
  const Axis c = locate(p > kPi ? 2.0f * kPi - p : p, 0.0f, kPi, res_.phi);
  Value out;
  for (int corner = 0; corner < 8; ++corner) {
    const float w = ((corner & 1) ? a.w : 1.0f - a.w) * ((corner & 2) ? b.w : 1.0f - b.w) *
                    ((corner & 4) ? c.w : 1.0f - c.w);
    if (w == 0.0f) continue;
    const Value e = entry((corner & 1) ? a.i1 : a.i0, (corner & 2) ? b.i1 : b.i0, (corner & 4) ? c.i1 : c.i0);
    out.diffuse += w * e.diffuse;
    out.specular += w * e.specular;
  }
  return out;
}

}  // namespace meso
