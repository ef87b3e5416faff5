// Becker & Max 1993, section 2.1: distr[theta_V][theta_N][phi_{N-V}], the distribution of visible
// normals of the displaced relief seen from polar angle theta_V (DESIGN.md section 4).
#pragma once

#include "meso/core/math.h"

#include <span>
#include <vector>

namespace meso {

struct HistogramResolution {
  int thetaV = 16;  // view slices, theta_V = k * thetaVMax / (thetaV - 1)
  int thetaN = 96;  // normal polar bins, uniform in theta_N over [0, pi/2]; fine, because the
                    // redistribution CDFs need the tails of steep reliefs (measured by chi-square)
  int phi = 32;     // azimuth bins of phi_{N-V} = phi_N - phi_V, uniform over [-pi, pi)
  // View azimuth slices phi_V over [0, 2 pi), centres at 2 pi (a + 1/2) / phiV: 1 averages all view
  // azimuths (the paper's isotropic relief); more keep an anisotropic relief's dependence on where
  // it is seen from (docs/metric.md).
  int phiV = 1;
};

// The last view slice of a histogram: 89 degrees.
inline constexpr float kThetaVMax = 1.5533430f;

// A normal as angles relative to the view: theta_N from the macro normal, phi = phi_N - phi_V.
struct NormalAngles {
  float thetaN = 0.0f;
  float phi = 0.0f;
};

// Probability masses per bin: each view slice sums to 1 after normalize(). A view slice k is one
// (theta_V, phi_V) pair, k = iThetaV * phiV + iPhiV (with phiV = 1, k is the theta_V index). The
// slices at theta_V = 0 are the bump distribution f. The phi axis is relative to the view azimuth;
// with phiV = 1 it is averaged over many phi_V, i.e. the relief is treated as isotropic (the
// paper's assumption).
class VisibleNormalHistogram {
 public:
  // thetaVMax < pi/2: exactly grazing rays see only silhouettes, so the last slice is taken just
  // above the horizon and lookups beyond it clamp to it.
  explicit VisibleNormalHistogram(HistogramResolution res, float thetaVMax = kThetaVMax);
  // The bin geometry alone, with no storage (for tables that only need the layout).
  struct LayoutOnly {};
  VisibleNormalHistogram(HistogramResolution res, float thetaVMax, LayoutOnly);

  const HistogramResolution& resolution() const { return res_; }
  float thetaVMax() const { return thetaVMax_; }
  float thetaV(int k) const;  // view angle of theta_V index k
  int numSlices() const { return res_.thetaV * res_.phiV; }
  int sliceOf(int iThetaV, int iPhiV) const { return iThetaV * res_.phiV + iPhiV; }
  float sliceThetaV(int slice) const { return thetaV(slice / res_.phiV); }
  float slicePhiV(int slice) const { return phiVCentre(slice % res_.phiV); }
  float phiVCentre(int a) const {
    return 2.0f * kPi * (static_cast<float>(a) + 0.5f) / static_cast<float>(res_.phiV);
  }
  float thetaNWidth() const;  // bin width in theta_N
  float phiWidth() const;     // bin width in phi
  float thetaNCentre(int i) const;
  float phiCentre(int j) const;
  int thetaNBin(float thetaN) const;  // clamped into range
  int phiBin(float phi) const;        // phi wrapped into [-pi, pi)
  float solidAngle(int i) const;      // of one (theta_N bin i, phi bin) cell

  float& mass(int k, int i, int j) { return data_[index(k, i, j)]; }
  float mass(int k, int i, int j) const { return data_[index(k, i, j)]; }
  std::span<const float> slice(int k) const;
  // Counts one visible normal (weight = its share of projected area). `normal` is the unit normal
  // in the view-aligned frame (view azimuth along +x, macro normal +z); its angles pick the bin.
  void add(int k, const Vec3& normal, float weight = 1.0f);
  // add() in two steps, for normals added to many slices: the bin of a normal within a slice,
  // and adding to bin `bin` of slice k (the same sums as add(k, normal, weight)).
  size_t binInSlice(const Vec3& normal) const;
  void addToBin(int k, size_t bin, const Vec3& normal, float weight) {
    const size_t b = static_cast<size_t>(k) * res_.thetaN * res_.phi + bin;
    data_[b] += weight;
    if (!normalSums_.empty()) normalSums_[b] += weight * normal;
  }
  // Scales each slice to sum 1 and turns the normal sums into per-bin means; an empty slice gets
  // all its mass in the theta_N = 0 bins (flat).
  void normalize();
  // Mean of the normals counted in a bin (not renormalized: sum of mass * meanNormal is exactly the
  // mean visible normal). A bin that received mass by mass() only returns its centre direction.
  Vec3 meanNormal(int k, int i, int j) const;
  // Masses then (withNormals) mean normals as one float array, and back: fromData takes either
  // layout and returns false (leaving the histogram unchanged) if the size matches neither. Without
  // normals, meanNormal gives bin centres. The table cache stores masses only: mean normals serve
  // the BRDF integration, and the BRDF is cached itself.
  std::vector<float> toData(bool withNormals = true) const;
  bool fromData(std::span<const float> data);
  size_t numBins() const { return data_.size(); }
  // Frees the mean normals once the tables that need them are built (a quarter of the memory).
  void dropMeanNormals() { std::vector<Vec3>().swap(normalSums_); }
  // Unit direction of a bin centre in the view-aligned frame (theta_N = 0 bin: its centre too).
  Vec3 binDirection(int i, int j) const;

 private:
  size_t index(int k, int i, int j) const {
    return (static_cast<size_t>(k) * res_.thetaN + i) * res_.phi + j;
  }
  HistogramResolution res_;
  float thetaVMax_;
  std::vector<float> data_;
  std::vector<Vec3> normalSums_;  // per bin; after normalize(), per-bin mean normals
};

// The angles of a unit normal in the view-aligned frame.
NormalAngles anglesOf(const Vec3& n);
// The unit normal of given angles in the view-aligned frame.
Vec3 normalOf(NormalAngles a);

// Wraps an angle into [-pi, pi).
float wrapPi(float a);

}  // namespace meso
