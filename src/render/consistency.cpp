// Becker & Max 1993, Figure 6: area-averaged intensities of the four renderers on one relief.
#include "meso/render/consistency.h"

#include "meso/core/rng.h"
#include "meso/render/level_shading.h"
#include "meso/render/shading.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// The BRDF renderer with the level's self-shadowing: each of its terms scaled by its own factor.
double shadowedBrdf(const Material& material, const Light& light, const ViewFrame& frame,
                    const BrdfTable& brdf, const ShadowingTable::Value& S) {
  Material diffuse = material, specular = material;
  diffuse.ks = Vec3(0.0f);
  specular.kd = Vec3(0.0f);
  const Light lights[] = {light};
  return S.diffuse * shadeBrdf(diffuse, lights, Vec3(0.0f), frame, brdf).x +
         S.specular * shadeBrdf(specular, lights, Vec3(0.0f), frame, brdf).x;
}

// One azimuth of measureConsistency: the view at phiV, the light at phiV - phi.
ConsistencyRow measureAzimuth(const PeriodicRelief& relief, const PeriodicTile& tile,
                              const LevelTables& tables, float thetaV, const ConsistencySettings& s,
                              const Material& material, int a) {
  Rng rng(s.seed, static_cast<uint64_t>(a));
  const float phiV = 2.0f * kPi * (static_cast<float>(a) + 0.5f) / static_cast<float>(s.azimuths);
  const Vec3 V = polar(thetaV, phiV);
  Light light;
  light.direction = -polar(s.thetaL, phiV - s.phi);
  const Light lights[] = {light};
  const ViewFrame frame = makeViewFrame(Vec3(0.0f, 0.0f, 1.0f), V, Vec3(1.0f, 0.0f, 0.0f));
  // The tabulated self-shadowing at this view and light, for redistribution and the BRDF.
  LightShadows S;
  const ShadowingTable::Value sv =
      s.shadows ? tables.shadowing.lookup(thetaV, phiV, s.thetaL, s.phi) : ShadowingTable::Value{};
  S.light[0] = {sv.diffuse, sv.specular};
  const LightShadows* redistributionShadows = s.shadows ? &S : nullptr;
  const Vec3 L = -light.direction;
  const int side =
      std::max(1, static_cast<int>(std::sqrt(static_cast<double>(s.samplesPerAzimuth))));
  ConsistencyRow row;
  int hits = 0;
  for (int i = 0; i < side * side; ++i) {
    // Jittered strata over the tile: the area average of the smooth renderers.
    const Vec2 xy((static_cast<float>(i % side) + rng.uniform()) / side,
                  (static_cast<float>(i / side) + rng.uniform()) / side);
    const Vec3 P(xy, 0.0f);
    const Vec3 n = blinnNormal(relief, xy);
    row.bump += shadeLocal(material, lights, P, n, V).x;
    row.redistribution +=
        shadeLocal(material, lights, P, redistributeNormal(tables.redistribution, frame, 0.0f, n),
                   V, redistributionShadows)
            .x;
    // The displaced relief, projected-area weighted: uniform origins above it along -V; with
    // shadows a real shadow ray from each hit, lifted off the relief along its normal.
    Vec3 hit;
    if (tile.traceHit(Vec3(xy, tile.zMax() + 1e-3f), -V, hit)) {
      const Vec3 nHit = blinnNormal(relief, Vec2(hit));
      LightShadows visible;
      if (s.shadows && tile.occluded(hit + 1e-4f * nHit, L)) visible.light[0] = {0.0f, 0.0f};
      row.displacement += shadeLocal(material, lights, Vec3(Vec2(hit), 0.0f), nHit, V,
                                     s.shadows ? &visible : nullptr)
                              .x;
      ++hits;
    }
  }
  row.bump /= side * side;
  row.redistribution /= side * side;
  row.displacement /= std::max(hits, 1);
  row.brdf = s.shadows ? shadowedBrdf(material, light, frame, tables.brdf, sv)
                       : shadeBrdf(material, lights, Vec3(0.0f), frame, tables.brdf).x;
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
  char line[256];
  for (const ConsistencyRow& r : rows) {
    const double deg = r.thetaV * 180.0 / kPi;
    if (format == TableFormat::Csv)
      std::snprintf(line, sizeof line, "%.6g,%.6f,%.6f,%.6f,%.6f\n", deg, r.bump * scale,
                    r.redistribution * scale, r.brdf * scale, r.displacement * scale);
    else
      std::snprintf(line, sizeof line, "| %.4g | %.4f | %.4f | %.4f | %.4f | %.2f%% |\n", deg,
                    r.bump * scale, r.redistribution * scale, r.brdf * scale,
                    r.displacement * scale, 100.0 * worstPairwiseDifference(r));
    out += line;
  }
  return out;
}

}  // namespace meso
