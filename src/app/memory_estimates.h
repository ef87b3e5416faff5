// What a render needs in memory, estimated from the scene before anything is allocated (film,
// appearance tables, micropolygons); checked against the limit of core/memory_budget.h.
#pragma once

#include "meso/scene/scene.h"

#include <cstdint>
#include <string>

namespace meso::app {

// The film (11 float channels) and its encoded EXR and PNG.
double filmBytes(int width, int height);

// One relief level's tables at `r`: histograms (masses, normal sums, CDFs, cache copy), BRDF table
// and the traced relief mesh with its BVH. Sets *key to the [render.tables] key of the largest
// part.
double levelTablesBytes(const TableResolution& r, std::string* key);

// Refuses (meso::Error naming the key) a scene whose film or tables exceed `limitBytes`
// (--memory-limit), and returns their estimate, which prepareRenderContext takes off the limit with
// the limit surfaces before it fits the micropolygon cap (PrepareOptions::reservedBytes).
// withFilm false: only the tables (meso tables renders nothing).
double checkRenderMemory(const Scene& scene, uint64_t limitBytes, bool withFilm = true);

}  // namespace meso::app
