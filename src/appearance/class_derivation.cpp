// Becker & Max 1993, section 2.1 tables of a metric class through the affine map of its tile
// (class_derivation.h, docs/metric.md).
#include "meso/appearance/class_derivation.h"

#include "meso/appearance/table_axis.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace meso {
namespace {

// Sub-bin samples per tile bin, along theta_N and phi. Slopes map linearly, s -> A^-T s / t, whose
// singular values are sigma and 1 / sigma (A keeps areas): azimuths between normals stretch by up
// to sigma^2, slopes by up to sigma max(t, 1 / t). Two samples per class bin width at that stretch.
struct SubBins {
  int theta = 2;
  int phi = 2;
};

SubBins subBinsFor(const ClassMap& m) {
  const double a = m.shape.a, b = m.shape.b;
  const double squares = 1.0 / (a * a) + b * b + a * a;  // of A^-T = [[1/a, 0], [-b, a]]
  const double sigma =
      std::sqrt(0.5 * (squares + std::sqrt(std::max(squares * squares - 4.0, 0.0))));
  const double t = std::max<double>(m.t, 1.0 / m.t);
  const auto samples = [](double stretch) {
    return static_cast<int>(std::clamp(std::ceil(2.0 * stretch), 2.0, 8.0));
  };
  return {samples(sigma * t), samples(sigma * sigma)};
}

// The azimuth, in the tile, of the class's directions of azimuth phi (also of theta = 0, whose
// view-aligned frame still turns with phi).
float tileAzimuth(const ClassMap& m, float phi) {
  const Vec2 h = m.horizontalToTile({std::cos(phi), std::sin(phi)});
  return std::atan2(h.y, h.x);
}

// The tile's masses seen from the tile direction (thetaT, phiT): its slices around it mixed
// bilinearly, as the renderers mix them.
void interpolateSlices(const VisibleNormalHistogram& tile, float thetaT, float phiT,
                       std::vector<float>& out) {
  const HistogramResolution& r = tile.resolution();
  const TableAxis th = locateOnAxis(thetaT, 0.0f, tile.thetaVMax(), r.thetaV);
  const TableAxis ph = locateViewAzimuth(phiT, r.phiV);
  std::fill(out.begin(), out.end(), 0.0f);
  for (int kt = 0; kt < 2; ++kt)
    for (int kp = 0; kp < 2; ++kp) {
      const float w = (kt ? th.w : 1.0f - th.w) * (kp ? ph.w : 1.0f - ph.w);
      if (w == 0.0f) continue;
      const std::span<const float> s =
          tile.slice(tile.sliceOf(kt ? th.i1 : th.i0, kp ? ph.i1 : ph.i0));
      for (size_t b = 0; b < out.size(); ++b) out[b] += w * s[b];
    }
}

}  // namespace

VisibleNormalHistogram deriveHistogram(const VisibleNormalHistogram& tile, const ClassMap& map,
                                       const HistogramResolution& resolution, int azimuths) {
  VisibleNormalHistogram h(resolution);
  const HistogramResolution& r = h.resolution();
  const HistogramResolution& tr = tile.resolution();
  const SubBins sub = subBinsFor(map);
  // Sub-bin samples, uniform in angle within each tile bin.
  std::vector<float> sinT(static_cast<size_t>(tr.thetaN) * sub.theta), cosT(sinT.size());
  for (size_t q = 0; q < sinT.size(); ++q) {
    const float theta =
        (static_cast<float>(q) + 0.5f) / static_cast<float>(sub.theta) * tile.thetaNWidth();
    sinT[q] = std::sin(theta), cosT[q] = std::cos(theta);
  }
  const int perSlice = std::max(azimuths / r.phiV, 1);  // the traced azimuths of a slice
  const float massPerSample = 1.0f / static_cast<float>(sub.theta * sub.phi * perSlice);
  // Where each sub-bin sample of the tile lands in the class's view-aligned frame depends on the
  // view azimuth only (the tile's frame turns with phi_T, the class's with phi_V), not on theta_V:
  // found once per azimuth for every theta_V slice of it. One task per view-azimuth slice, its
  // theta_V slices in order, so every bin's sums run in the same order for any thread count.
  const size_t samplesPerAzimuth = sinT.size() * static_cast<size_t>(tr.phi) * sub.phi;
  tbb::parallel_for(0, r.phiV, [&](int m) {
    std::vector<float> masses(static_cast<size_t>(tr.thetaN) * tr.phi);
    std::vector<float> cosP(static_cast<size_t>(tr.phi) * sub.phi), sinP(cosP.size());
    std::vector<size_t> bins(perSlice * samplesPerAzimuth);
    std::vector<Vec3> normals(bins.size());
    std::vector<float> phiV(perSlice), phiT(perSlice);
    for (int q = 0; q < perSlice; ++q) {
      // The azimuths traceSlice traces for this slice.
      const int a = m * perSlice + q;
      phiV[q] = 2.0f * kPi * (static_cast<float>(a) + 0.5f) / static_cast<float>(perSlice * r.phiV);
      phiT[q] = tileAzimuth(map, phiV[q]);
      for (size_t p = 0; p < cosP.size(); ++p) {
        const float phi =
            -kPi + (static_cast<float>(p) + 0.5f) / static_cast<float>(sub.phi) * tile.phiWidth();
        cosP[p] = std::cos(phi + phiT[q]), sinP[p] = std::sin(phi + phiT[q]);
      }
      // Back into the class's view-aligned frame: rotate by -phi_V about z.
      const float c = std::cos(-phiV[q]), s = std::sin(-phiV[q]);
      size_t e = q * samplesPerAzimuth;
      for (int i = 0; i < tr.thetaN; ++i)
        for (int j = 0; j < tr.phi; ++j)
          for (int si = i * sub.theta; si < (i + 1) * sub.theta; ++si)
            for (int sj = j * sub.phi; sj < (j + 1) * sub.phi; ++sj, ++e) {
              const Vec3 n =
                  map.normalFromTile(Vec3(sinT[si] * cosP[sj], sinT[si] * sinP[sj], cosT[si]));
              normals[e] = Vec3(c * n.x - s * n.y, s * n.x + c * n.y, n.z);
              bins[e] = h.binInSlice(normals[e]);
            }
    }
    const size_t perBin = static_cast<size_t>(sub.theta) * sub.phi;
    for (int kt = 0; kt < r.thetaV; ++kt) {
      const int k = h.sliceOf(kt, m);
      const float thetaV = h.sliceThetaV(k);
      for (int q = 0; q < perSlice; ++q) {
        const Vec3 view = map.toTile(polarDirection(thetaV, phiV[q]));
        interpolateSlices(tile, std::acos(std::clamp(view.z, -1.0f, 1.0f)), phiT[q], masses);
        size_t e = q * samplesPerAzimuth;
        for (size_t b = 0; b < masses.size(); ++b, e += perBin) {
          const float mass = masses[b];
          if (!(mass > 0.0f)) continue;
          for (size_t x = e; x < e + perBin; ++x)
            h.addToBin(k, bins[x], normals[x], mass * massPerSample);
        }
      }
    }
  });
  h.normalize();
  return h;
}

ShadowingTable deriveShadowing(const ShadowingTable& tile, const ClassMap& map,
                               const VisibleNormalHistogram& layout, ShadowingResolution res,
                               ViewRows rows) {
  return ShadowingTable::tabulate(
      layout, res,
      [&](float thetaV, float phiV, float thetaL, float phiVL) {
        const Vec3 v = map.toTile(polarDirection(thetaV, phiV));
        const Vec3 l = map.toTile(polarDirection(thetaL, phiV - phiVL));
        const float phiT = tileAzimuth(map, phiV), phiLT = tileAzimuth(map, phiV - phiVL);
        return tile.lookup(std::acos(std::clamp(v.z, -1.0f, 1.0f)), phiT,
                           std::acos(std::clamp(l.z, -1.0f, 1.0f)), wrapAngle(phiT - phiLT));
      },
      rows);
}

}  // namespace meso
