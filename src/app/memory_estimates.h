// What a render needs in memory, estimated from the scene before anything is allocated (film,
// appearance tables, micropolygons); checked against the limit of core/memory_budget.h.
#pragma once

#include "meso/core/warnings.h"
#include "meso/scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace meso::app {

// The film (11 float channels) and its encoded EXR and PNG.
double filmBytes(int width, int height);

// One relief level's tables at `r`: histograms (masses, normal sums, CDFs, cache copy), BRDF table
// and the traced relief mesh with its BVH. Sets *key to the [render.tables] key of the largest
// part.
double levelTablesBytes(const TableResolution& r, std::string* key);

// Refuses (meso::Error naming the key) a scene whose film or tables exceed `limitBytes`
// (--memory-limit), and lowers render.max_micropolygons to what fits beside them (the cap becomes
// a memory cap), adding a warning when it does. withFilm false: only the tables (meso tables
// renders nothing).
void checkRenderMemory(Scene& scene, uint64_t limitBytes, Warnings& warnings, bool withFilm = true);

}  // namespace meso::app
