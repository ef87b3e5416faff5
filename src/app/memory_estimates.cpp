#include "memory_estimates.h"

#include "meso/core/memory_budget.h"

namespace meso::app {

double filmBytes(int width, int height) {
  const double pixels = static_cast<double>(width) * height;
  return pixels * (11 * 4     // film
                   + 11 * 4   // EXR encoded in memory (at most about the raw size)
                   + 3 + 3);  // PNG bytes and their encoding
}

double levelTablesBytes(const TableResolution& r, std::string* key) {
  const double slices = static_cast<double>(r.thetaVBins) * r.phiVBins;
  const double histograms = slices * r.thetaNBins * r.phiBins * (4 + 12 + 4 + 4);
  const double brdf = slices * (2 * r.brdfThetaL - 1) * r.brdfPhi * 2 * 4 * 2;
  const double relief = static_cast<double>(r.meshResolution) * r.meshResolution * 2 * 96;
  if (key)
    *key = histograms >= brdf && histograms >= relief ? "render.tables.theta_n_bins/phi_bins"
           : brdf >= relief                           ? "render.tables.brdf_theta_l/brdf_phi"
                                                      : "render.tables.mesh_resolution";
  return histograms + brdf + relief;
}

double checkRenderMemory(const Scene& scene, uint64_t limitBytes, bool withFilm) {
  const std::string file = scene.file.string();
  const double film = withFilm ? filmBytes(scene.camera.width, scene.camera.height) : 0.0;
  requireMemoryWithin(limitBytes, film, file, "camera.resolution",
                      "the film of " + std::to_string(scene.camera.width) + "x" +
                          std::to_string(scene.camera.height) +
                          " pixels, 11 float channels, and its EXR and PNG");
  std::string key;
  size_t levels = 0;
  for (const Material& m : scene.materials) levels += m.relief.size();
  const double tables = static_cast<double>(levels) * levelTablesBytes(scene.render.tables, &key);
  requireMemoryWithin(limitBytes, film + tables, file, key,
                      "the appearance tables of " + std::to_string(levels) +
                          " relief level(s) at [render.tables] " + formatMib(tables) +
                          ", and the film " + formatMib(film));
  return film + tables;
}

}  // namespace meso::app
