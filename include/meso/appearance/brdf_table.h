// Becker & Max 1993, section 2.1 and Figure 2: BRDF_diff and BRDF_spec[theta_V][theta_L][phi_{V-L}]
// built from visible-normal distributions, looked up trilinearly.
#pragma once

#include "meso/appearance/table_axis.h"

#include "meso/appearance/visible_normal_histogram.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace meso {

// The highlight of one visible normal n as a function of cos(angle between H and n), peak 1 at
// cos = 1 for (H.n)^phong. A finest level whose material synthesizes detail below it (an NDF)
// uses the NDF's lobe instead (Figure 2's first branch over the NDF model).
struct SpecularLobe {
  std::function<float(float cosHN)> value;
  uint64_t fingerprint = 0;  // identifies the lobe in table cache keys
};

// How the integration groups a view slice's histogram bins into quadrature normals: neighbouring
// bins spanning at most these widths (radians; at least one bin) become one point at their
// mass-weighted mean normal. The diffuse term is linear in N, so it stays exact; the specular and
// finer-level terms are off to second order in the group's spread. 0: every bin its own point.
struct NormalGrouping {
  float thetaN = 0.0f;
  float phi = 0.0f;
  // Bins per group on a histogram of the given bin widths.
  int thetaNBins(float width) const;
  int phiBins(float width) const;
};

// Which vector instructions the finest level's Phong integration uses: the CPU's widest that meso
// compiles for (AVX2 on x86-64 where the CPU has it) or the baseline's. The tables are the same
// bits either way; `baseline` is there to test that.
enum class BrdfVectors { best, baseline };
void setBrdfVectors(BrdfVectors v);
bool brdfHasWiderVectors();  // whether `best` differs from `baseline` on this CPU

struct BrdfResolution {
  int thetaL = 16;  // nodes over [0, pi/2], both ends included; the table continues at the same
                    // spacing to pi (thetaLNodes), for lights below the mean plane that relief
                    // facets still face
  int phi = 16;     // nodes of |phi_{V-L}| over [0, pi], both ends included (isotropic relief)
  // Quadrature of the finest level's local model and of the coarser levels' eq. (1): groups of
  // 1.875 x 11.25 and 3.75 x 22.5 degrees (2 x 1 and 4 x 2 bins of the default 96 x 32 histogram)
  // moved the default scene's BRDF image by 0.02% per depth band against every bin its own point,
  // for a sixth of the BRDF's build time (twice those widths: 0.07%; docs/tables.md).
  NormalGrouping finest{0.0327249f, 0.196350f};
  NormalGrouping coarser{0.0654498f, 0.392699f};
};

// Each entry is the area-averaged reflectance of the relief seen from V and lit from L, per unit
// kd (diffuse) or ks (specular): the shaded intensity of a pixel is ka + kd * diffuse + ks *
// specular (times the light), which is what bump and displacement give when averaged over the same
// area.
class BrdfTable {
 public:
  BrdfTable() = default;
  // The finest level (Figure 2, first branch): (L.N) and (H.N)^phong over the visible normals.
  // Every table is integrated on the theta_V rows `rows` only (the others stay 0 and are never
  // looked up: lookups clamp to the rows built); each row is the same bits as on a whole table.
  static BrdfTable fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res,
                                    float phong, ViewRows rows = {});
  // The same with any specular lobe.
  static BrdfTable fromDistribution(const VisibleNormalHistogram& distr, BrdfResolution res,
                                    const SpecularLobe& lobe, ViewRows rows = {});
  // A coarser level (Figure 2, second branch): the finer level's table at the primed angles of
  // eq. (1), averaged over this level's visible normals.
  static BrdfTable fromFinerLevel(const VisibleNormalHistogram& distr, BrdfResolution res,
                                  const BrdfTable& finer, ViewRows rows = {});

  struct Value {
    float diffuse = 0.0f;
    float specular = 0.0f;
  };
  // Trilinear lookup; angles are clamped to the table (theta_V beyond the last slice uses it, and
  // beyond the rows built the nearest of them).
  // On a table with view-azimuth slices, the phi_V = 0 ones (use the overload below).
  Value lookup(float thetaV, float thetaL, float phiVL) const;
  // With the view's azimuth phiV about the relief's own axes (tile x = 0): interpolated between
  // view-azimuth slices too; phiVL = phi_V - phi_L is signed on such a table (an anisotropic relief
  // is not mirror-symmetric about the view plane), |phiVL| on an isotropic one.
  Value lookup(float thetaV, float phiV, float thetaL, float phiVL) const;
  int numPhiV() const { return phiV_; }
  // A view located once on the (theta_V, phi_V) axes, for many lookups from it (eq. 1 looks up
  // every light of a table from each visible normal).
  struct ViewAxes {
    TableAxis thetaV, phiV;
  };
  ViewAxes locateView(float thetaV, float phiV) const;
  Value lookup(const ViewAxes& view, float thetaL, float phiVL) const;
  // Nodes on the phi_{V-L} axis: res.phi over [0, pi] (isotropic), 2 res.phi - 1 over [-pi, pi].
  static int phiNodes(const BrdfResolution& res, int phiV) {
    return phiV > 1 ? 2 * res.phi - 1 : res.phi;
  }
  // Nodes on the theta_L axis: 2 res.thetaL - 1 over [0, pi] (res.thetaL of them up to pi / 2).
  static int thetaLNodes(const BrdfResolution& res) { return 2 * res.thetaL - 1; }
  // Floats in a table's data(): diffuse and specular per (theta_V, phi_V, theta_L, phi_{V-L}) node.
  static size_t dataSize(const BrdfResolution& res, int thetaV, int phiV) {
    return 2 * static_cast<size_t>(thetaV) * std::max(phiV, 1) * thetaLNodes(res) *
           phiNodes(res, phiV);
  }

  int numThetaV() const { return static_cast<int>(thetaV_.size()); }
  const BrdfResolution& resolution() const { return res_; }
  float thetaV(int k) const { return thetaV_[k]; }
  float thetaL(int i) const;
  float phi(int j) const;
  Value entry(int k, int i, int j) const;
  // Raw storage for the cache and for checks (diffuse then specular, k-major).
  const std::vector<float>& data() const { return data_; }
  static BrdfTable fromData(std::vector<float> thetaV, BrdfResolution res, std::vector<float> data,
                            int phiV = 1);
  // The theta_V rows that hold values (a table read from the cache is told which).
  const ViewRows& viewRows() const { return rows_; }
  void setViewRows(ViewRows rows) { rows_ = rows; }

 private:
  TableLayout layout() const {
    return {data_.data(), data_.data() + data_.size() / 2, phiV_, thetaLNodes(res_), nPhi_};
  }
  // k is a view slice: iThetaV * phiV + iPhiV.
  size_t index(int k, int i, int j) const {
    return (static_cast<size_t>(k) * thetaLNodes(res_) + i) * nPhi_ + j;
  }
  std::vector<float> thetaV_;
  BrdfResolution res_;
  int phiV_ = 1;
  int nPhi_ = 16;
  std::vector<float> data_;  // dataSize(res_, view slices, phiV_)
  ViewRows rows_;
};

}  // namespace meso
