// Becker & Max 1993, Figure 6: area-averaged intensities of the four renderers on one relief.
#include "meso/render/consistency.h"

#include "meso/core/rng.h"
#include "meso/render/level_shading.h"
#include "meso/render/relief_shadowing.h"
#include "meso/render/shading.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <vector>

namespace meso {
namespace {

Vec3 polar(float theta, float phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Material materialFor(const ConsistencySettings& s) {
  Material m;
  m.ka = Vec3(0.0f);
  m.kd = Vec3(s.component == Component::Specular ? 0.0f : 1.0f);
  m.ks = Vec3(s.component == Component::Diffuse ? 0.0f : 1.0f);
  m.phong = s.phong;
  return m;
}

Vec3 blinnNormal(const PeriodicRelief& relief, Vec2 xy) {
  const Vec2 g = relief.gradient(xy.x, xy.y);
  return glm::normalize(Vec3(-g.x, -g.y, 1.0f));
}

// The lights of one sample point: the directional light at (thetaL, phiV - phi), the same for
// every point, or s.lightSamples directions of the environment drawn for the point
// (environmentLights), shared by the four renderers there so that their differences carry little
// sampling noise. An environment's directions below the patch's plane light nothing: the relief
// lies on an opaque surface.
class PatchLights {
 public:
  PatchLights(const ConsistencySettings& s, float phiV)
      : s_(s),
        n_(s.environment ? static_cast<size_t>(std::clamp(s.lightSamples, 1, kMaxSampleLights))
                         : 1) {
    storage_[0].direction = -polar(s.thetaL, phiV - s.phi);
  }
  std::span<const Light> at(uint64_t key) {
    const std::span<Light> lights(storage_.data(), n_);
    if (!s_.environment) return lights;
    environmentLights(*s_.environment, key, lights);
    for (Light& l : lights)
      if (!(l.direction.z < 0.0f)) l.colour = Vec3(0.0f);
    return lights;
  }

 private:
  const ConsistencySettings& s_;
  size_t n_;
  std::array<Light, kMaxSampleLights> storage_{};
};

// One azimuth of measureConsistency, every renderer by the renderer's own functions on the unit
// tile (an identity TileMap): the view at phiV.
ConsistencyRow measureAzimuth(const PeriodicRelief& relief, const PeriodicTile& tile,
                              const LevelTables& tables, float thetaV, const ConsistencySettings& s,
                              const Material& material, int a) {
  Rng rng(s.seed, static_cast<uint64_t>(a));
  const float phiV = 2.0f * kPi * (static_cast<float>(a) + 0.5f) / static_cast<float>(s.azimuths);
  // theta_V = 0 as the limit of near-normal views, which keep their azimuth phiV: the tables'
  // view-azimuth slices are then looked up at it, as in an image, not all at the tangent hint's
  // azimuth (docs/environment.md measures the difference).
  const Vec3 V = polar(std::max(thetaV, 1e-3f), phiV);
  const TileMap m;
  ShadowingLevels levels;
  if (s.shadows) levels.add(tables.shadowing, tables.shadowing);
  const LightShadows lit;
  // A white light's intensity is any channel; an environment's colours count by their luminance.
  const auto value = [&](const Vec3& c) -> double { return s.environment ? luminance(c) : c.x; };
  PatchLights patchLights(s, phiV);
  const int side =
      std::max(1, static_cast<int>(std::sqrt(static_cast<double>(s.samplesPerAzimuth))));
  ConsistencyRow row;
  int hits = 0;
  for (int i = 0; i < side * side; ++i) {
    // Jittered strata over the tile: the area average of the smooth renderers.
    const Vec2 xy((static_cast<float>(i % side) + rng.uniform()) / side,
                  (static_cast<float>(i / side) + rng.uniform()) / side);
    const std::span<const Light> lights =
        patchLights.at(mix64(s.seed ^ mix64(static_cast<uint64_t>(a) << 32 | i)));
    const Vec3 P(xy, 0.0f);
    const Vec3 n = blinnNormal(relief, xy);
    // The tabulated self-shadowing at this view and each light, for redistribution and the BRDF.
    const LightShadows S = reliefShadowing(lights, P, m, V, levels);
    row.bump += value(shadeLocal(material, lights, P, n, V));
    row.redistribution +=
        value(shadeLocal(material, lights, P, redistributeNormal(tables.redistribution, m, V, 0, n),
                         V, s.shadows ? &S : nullptr));
    // The BRDF does not depend on the point: one lookup serves a directional light.
    if (s.environment || i == 0)
      row.brdf += value(shadeBrdfShadowed(material, lights, P, m, V, tables.brdf, tables.brdf, 0.0f,
                                          lit, levels));
    // The displaced relief, projected-area weighted: uniform origins above it along -V; with
    // shadows a real shadow ray from each hit to each light, lifted off the relief along its
    // normal.
    Vec3 hit;
    if (tile.traceHit(Vec3(xy, tile.zMax() + 1e-3f), -V, hit)) {
      const Vec3 nHit = blinnNormal(relief, Vec2(hit));
      LightShadows visible;
      for (size_t k = 0; s.shadows && k < lights.size(); ++k)
        if (lights[k].colour != Vec3(0.0f) &&
            tile.occluded(hit + 1e-4f * nHit, -lights[k].direction))
          visible.light[k] = {0.0f, 0.0f};
      row.displacement += value(shadeLocal(material, lights, Vec3(Vec2(hit), 0.0f), nHit, V,
                                           s.shadows ? &visible : nullptr));
      ++hits;
    }
  }
  row.bump /= side * side;
  row.redistribution /= side * side;
  if (s.environment) row.brdf /= side * side;
  row.displacement /= std::max(hits, 1);
  return row;
}

}  // namespace

ConsistencyRow measureConsistency(const PeriodicRelief& relief, const PeriodicTile& tile,
                                  const LevelTables& tables, float thetaV,
                                  const ConsistencySettings& s) {
  const Material material = materialFor(s);
  std::vector<ConsistencyRow> perAzimuth(s.azimuths);
  tbb::parallel_for(0, s.azimuths, [&](int a) {
    perAzimuth[a] = measureAzimuth(relief, tile, tables, thetaV, s, material, a);
  });
  ConsistencyRow total;
  total.thetaV = thetaV;
  for (const ConsistencyRow& r : perAzimuth) {
    total.bump += r.bump / s.azimuths;
    total.redistribution += r.redistribution / s.azimuths;
    total.brdf += r.brdf / s.azimuths;
    total.displacement += r.displacement / s.azimuths;
  }
  return total;
}

double worstPairwiseDifference(const ConsistencyRow& r) {
  const double v[3] = {r.redistribution, r.brdf, r.displacement};
  double worst = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j && v[j] != 0.0) worst = std::max(worst, std::abs(v[i] - v[j]) / std::abs(v[j]));
  return worst;
}

std::string formatConsistency(const std::vector<ConsistencyRow>& rows, TableFormat format,
                              double normalizeTo) {
  const double scale = normalizeTo > 0.0 && !rows.empty() && rows.front().bump > 0.0
                           ? normalizeTo / rows.front().bump
                           : 1.0;
  std::string out = format == TableFormat::Csv
                        ? "theta_v,bump,redistribution,brdf,displacement\n"
                        : "| theta_V | bump | redistribution | brdf | displacement | worst pair "
                          "|\n|---|---|---|---|---|---|\n";
  for (const ConsistencyRow& r : rows) {
    const double deg = r.thetaV * 180.0 / kPi;
    if (format == TableFormat::Csv)
      fmt::format_to(std::back_inserter(out), "{:.6g},{:.6f},{:.6f},{:.6f},{:.6f}\n", deg,
                     r.bump * scale, r.redistribution * scale, r.brdf * scale,
                     r.displacement * scale);
    else
      fmt::format_to(std::back_inserter(out),
                     "| {:.4g} | {:.4f} | {:.4f} | {:.4f} | {:.4f} | {:.2f}% |\n", deg,
                     r.bump * scale, r.redistribution * scale, r.brdf * scale,
                     r.displacement * scale, 100.0 * worstPairwiseDifference(r));
  }
  return out;
}

}  // namespace meso
