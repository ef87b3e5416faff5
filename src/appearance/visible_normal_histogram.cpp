// Becker & Max 1993, section 2.1: the table of visible-normal distributions.
#include "meso/appearance/visible_normal_histogram.h"

#include "meso/core/math.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace meso {

float wrapPi(float a) {
  if (!std::isfinite(a)) return 0.0f;
  a = std::fmod(a + kPi, 2.0f * kPi);
  if (a < 0.0f) a += 2.0f * kPi;
  a -= kPi;
  return a >= kPi ? -kPi : a;
}

VisibleNormalHistogram::VisibleNormalHistogram(HistogramResolution res, float thetaVMax)
    : res_(res), thetaVMax_(thetaVMax) {
  res_.thetaV = std::max(res_.thetaV, 2);
  res_.thetaN = std::max(res_.thetaN, 1);
  res_.phi = std::max(res_.phi, 1);
  res_.phiV = std::max(res_.phiV, 1);
  data_.assign(static_cast<size_t>(numSlices()) * res_.thetaN * res_.phi, 0.0f);
  normalSums_.assign(data_.size(), Vec3(0.0f));
}

VisibleNormalHistogram::VisibleNormalHistogram(HistogramResolution res, float thetaVMax, LayoutOnly)
    : res_(res), thetaVMax_(thetaVMax) {
  res_.thetaV = std::max(res_.thetaV, 2);
  res_.thetaN = std::max(res_.thetaN, 1);
  res_.phi = std::max(res_.phi, 1);
  res_.phiV = std::max(res_.phiV, 1);
}

NormalAngles anglesOf(const Vec3& n) {
  const float z = std::clamp(n.z, -1.0f, 1.0f);
  return {fastAcos(z), (n.x == 0.0f && n.y == 0.0f) ? 0.0f : fastAtan2(n.y, n.x)};
}

Vec3 normalOf(NormalAngles a) {
  const float s = std::sin(a.thetaN);
  return {s * std::cos(a.phi), s * std::sin(a.phi), std::cos(a.thetaN)};
}

Vec3 VisibleNormalHistogram::binDirection(int i, int j) const {
  return normalOf({thetaNCentre(i), phiCentre(j)});
}

Vec3 VisibleNormalHistogram::meanNormal(int k, int i, int j) const {
  if (normalSums_.empty()) return binDirection(i, j);
  const Vec3& s = normalSums_[index(k, i, j)];
  return s == Vec3(0.0f) ? binDirection(i, j) : s;
}

float VisibleNormalHistogram::thetaV(int k) const {
  return thetaVMax_ * static_cast<float>(k) / static_cast<float>(res_.thetaV - 1);
}
float VisibleNormalHistogram::thetaNWidth() const {
  return 0.5f * kPi / static_cast<float>(res_.thetaN);
}
float VisibleNormalHistogram::phiWidth() const { return 2.0f * kPi / static_cast<float>(res_.phi); }
float VisibleNormalHistogram::thetaNCentre(int i) const {
  return (static_cast<float>(i) + 0.5f) * thetaNWidth();
}
float VisibleNormalHistogram::phiCentre(int j) const {
  return -kPi + (static_cast<float>(j) + 0.5f) * phiWidth();
}

int VisibleNormalHistogram::thetaNBin(float thetaN) const {
  const int i = static_cast<int>(std::floor(thetaN / thetaNWidth()));
  return std::clamp(i, 0, res_.thetaN - 1);
}

int VisibleNormalHistogram::phiBin(float phi) const {
  const int j = static_cast<int>(std::floor((wrapPi(phi) + kPi) / phiWidth()));
  return std::clamp(j, 0, res_.phi - 1);
}

float VisibleNormalHistogram::solidAngle(int i) const {
  const float a = static_cast<float>(i) * thetaNWidth();
  return (std::cos(a) - std::cos(a + thetaNWidth())) * phiWidth();
}

std::span<const float> VisibleNormalHistogram::slice(int k) const {
  const size_t n = static_cast<size_t>(res_.thetaN) * res_.phi;
  return {data_.data() + k * n, n};
}

size_t VisibleNormalHistogram::binInSlice(const Vec3& normal) const {
  const NormalAngles a = anglesOf(normal);
  return index(0, thetaNBin(a.thetaN), phiBin(a.phi));
}

void VisibleNormalHistogram::add(int k, const Vec3& normal, float weight) {
  const NormalAngles a = anglesOf(normal);
  const size_t b = index(k, thetaNBin(a.thetaN), phiBin(a.phi));
  data_[b] += weight;
  if (!normalSums_.empty()) normalSums_[b] += weight * normal;
}

void VisibleNormalHistogram::normalize() {
  const size_t n = static_cast<size_t>(res_.thetaN) * res_.phi;
  for (int k = 0; k < numSlices(); ++k) {
    float* s = data_.data() + k * n;
    const double sum = std::accumulate(s, s + n, 0.0);
    if (sum > 0.0) {
      for (size_t i = 0; i < n; ++i) {
        if (!normalSums_.empty() && s[i] > 0.0f) normalSums_[k * n + i] /= s[i];
        s[i] = static_cast<float>(s[i] / sum);
      }
    } else {
      for (int j = 0; j < res_.phi; ++j) s[j] = 1.0f / static_cast<float>(res_.phi);
    }
  }
}

}  // namespace meso

namespace meso {

std::vector<float> VisibleNormalHistogram::toData(bool withNormals) const {
  std::vector<float> out(data_);
  if (!withNormals) return out;
  for (size_t i = 0; i < data_.size(); ++i) {
    const Vec3 n = normalSums_.empty() ? Vec3(0.0f) : normalSums_[i];
    out.insert(out.end(), {n.x, n.y, n.z});
  }
  return out;
}

bool VisibleNormalHistogram::fromData(std::span<const float> data) {
  if (data.size() == data_.size()) {
    std::copy(data.begin(), data.end(), data_.begin());
    dropMeanNormals();
    return true;
  }
  if (data.size() != 4 * data_.size()) return false;
  normalSums_.assign(data_.size(), Vec3(0.0f));
  std::copy(data.begin(), data.begin() + data_.size(), data_.begin());
  for (size_t i = 0; i < normalSums_.size(); ++i) {
    const float* p = data.data() + data_.size() + 3 * i;
    normalSums_[i] = Vec3(p[0], p[1], p[2]);
  }
  return true;
}

}  // namespace meso
