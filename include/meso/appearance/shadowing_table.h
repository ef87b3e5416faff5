// Relief self-shadowing for the far-field renderers (DESIGN.md section 6; Becker & Max 1993,
// section 4.2): S(theta_V, phi_V, theta_L, phi_{V-L}), traced in the periodic tile.
#pragma once

#include "meso/appearance/table_axis.h"

#include "meso/appearance/histogram_builder.h"
#include "meso/appearance/periodic_tile.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace meso {

// A shadow ray still below the relief's highest point after this many tiles (a light at the
// horizon) counts as blocked. Part of the cache key.
inline constexpr int kShadowMaxTiles = 16;

struct ShadowingResolution {
  // theta_L is tabulated as its offset from theta_V, delta = theta_L - theta_V in [-pi/2, pi/2]
  // (2 thetaL - 1 nodes, 5 degree steps by default), so that interpolating between theta_V slices
  // follows the hot spot: S rises sharply to 1 as L nears V (what is seen is lit), a ridge along
  // theta_L = theta_V that a theta_L axis would blur (3% too dark at theta_V 80, theta_L 75).
  int thetaL = 19;
  // theta_V nodes: the histogram's slices subdivided this many times (S is curved along the ridge:
  // with the histogram's 16 slices it came out 1-2% too dark between them at theta_L 75).
  int thetaVRefine = 2;
  int phi = 7;  // nodes of |phi_{V-L}| over [0, pi] (signed tables: 2 phi - 1 over [-pi, pi])
  // Visible hits traced per (theta_V, phi_V) slice (x 32 on isotropic tables). S is smooth and
  // interpolated between many slices: 128 moved the terrain's BRDF and redistribution images by at
  // most 0.05% per depth band against 512, for a quarter of the cost (docs/tables.md).
  int raysPerSlice = 128;
  int azimuthsPerSlice =
      4;  // view azimuths those hits spread over within a slice (x 8 on isotropic tables)
};

// The fraction of the reflected light of the visible relief that is lit: at each visible hit seen
// from V (orthographic rays through the periodic copies of the tile, as the histograms trace) a
// shadow ray towards L, and
//   S_diff = sum lit (L.n)+ / sum (L.n)+,   S_spec = sum lit (H.n)+^phong / sum (H.n)+^phong.
// An unshadowed BRDF table times S is exactly the table that a shadow ray at every visible hit
// would have built (for the finest level; the diffuse and specular sums are the BRDF's own), and
// redistribution bump mapping, whose visible normals have the BRDF's mean, times S has the mean of
// displacement with real shadow rays. A factor rather than a second traced BRDF: it is smooth in
// V and L (so it needs fewer nodes than the BRDF), and one table serves the BRDF and
// redistribution.
class ShadowingTable {
 public:
  ShadowingTable() = default;
  // Traces the table on the slices of `layout` (theta_V nodes and view-azimuth slices), on the
  // histogram's theta_V rows `rows` only (the others stay 1, and lookups clamp to the rows built;
  // each row is the same bits as on a whole table).
  static ShadowingTable trace(const PeriodicRelief& relief, const PeriodicTile& tile,
                              const VisibleNormalHistogram& layout,
                              const HistogramSettings& histogram, ShadowingResolution res,
                              float phong, uint64_t seed, ViewRows rows = {});
  // The same table with one shadow ray (PeriodicTile::occluded) per visible hit and light node
  // instead of one horizon march per hit and light azimuth: the reference trace() is tested
  // against, many times slower.
  static ShadowingTable traceWithShadowRays(const PeriodicRelief& relief, const PeriodicTile& tile,
                                            const VisibleNormalHistogram& layout,
                                            const HistogramSettings& histogram,
                                            ShadowingResolution res, float phong, uint64_t seed);

  struct Value {
    float diffuse = 1.0f;
    float specular = 1.0f;
  };
  // The table on the nodes trace() fills, each node's value f(theta_V, phi_V, theta_L, phi_{V-L})
  // (phi_V the slice's centre): a table derived from another class's (class_derivation.h).
  using NodeFunction = std::function<Value(float, float, float, float)>;
  static ShadowingTable tabulate(const VisibleNormalHistogram& layout, ShadowingResolution res,
                                 const NodeFunction& f, ViewRows rows = {});
  // Multilinear in (theta_V, phi_V, theta_L - theta_V, phi_{V-L}); an empty table is 1.
  Value lookup(float thetaV, float phiV, float thetaL, float phiVL) const;
  bool empty() const { return data_.empty(); }

  int numThetaV() const { return static_cast<int>(thetaV_.size()); }
  int numPhiV() const { return phiV_; }
  const ShadowingResolution& resolution() const { return res_; }
  static int phiNodes(const ShadowingResolution& res, int phiV) {
    return phiV > 1 ? 2 * res.phi - 1 : res.phi;
  }
  int numDelta() const { return 2 * res_.thetaL - 1; }
  float delta(int i) const;  // theta_L - theta_V of node i
  float phi(int j) const;
  Value entry(int slice, int i, int j) const;
  // For the cache: theta_V nodes, then phiV, then diffuse and specular factors.
  std::vector<float> toData() const;
  static bool fromData(const std::vector<float>& data, ShadowingResolution res,
                       ShadowingTable& out);
  // The histogram's theta_V rows that hold values (a table read from the cache is told which).
  void setViewRows(ViewRows rows) { rows_ = rows.refined(std::max(res_.thetaVRefine, 1)); }

 private:
  TableLayout layout() const {
    return {data_.data(), data_.data() + data_.size() / 2, phiV_, numDelta(), nPhi_};
  }
  static ShadowingTable onNodes(const VisibleNormalHistogram& layout, ShadowingResolution res);
  static ShadowingTable traceWith(const PeriodicRelief& relief, const PeriodicTile& tile,
                                  const VisibleNormalHistogram& layout,
                                  const HistogramSettings& histogram, ShadowingResolution res,
                                  float phong, uint64_t seed, bool withShadowRays, ViewRows rows);
  size_t index(int slice, int i, int j) const {
    return (static_cast<size_t>(slice) * numDelta() + i) * nPhi_ + j;
  }
  std::vector<float> thetaV_;
  ShadowingResolution res_;
  int phiV_ = 1;
  int nPhi_ = 7;
  std::vector<float> data_;  // diffuse then specular, 2 * slices * thetaL * nPhi
  ViewRows rows_;            // on the refined theta_V nodes
};

}  // namespace meso
