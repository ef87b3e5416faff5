// Becker & Max 1993, section 4.3: a height image as several band-limited levels, each with its own
// T (DESIGN.md section 1).
#pragma once

#include "meso/core/memory_budget.h"
#include "meso/scene/scene.h"

#include <vector>

namespace meso {

// The levels one `[[materials.relief]]` height image stands for: its octave bands
// (relief/band_split.h planBands: d.bands of them, 0 = as many as the image holds), bands with less
// than 5% of the image's slope energy merged into a neighbour, at most maxLevels. Each level is a
// copy of d with bandCount, bandFirst and bandLast set, and the user's midlevel on the coarsest
// level only (the finer bands have mean 0). A noise relief, or an image with bands = 1, is
// returned as it is. Throws meso::Error located at d.loc for an image that cannot be read.
// Images larger than memoryLimitBytes allows are refused before they are decoded.
std::vector<ReliefLevelDecl> expandImageBands(
    const ReliefLevelDecl& d, int maxLevels, uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

// Every material's height images as their levels, each image within what the material's other
// relief tables leave of kMaxMaterialReliefLevels. loadScene does this; a scene parsed from text
// keeps one level per image until it is called.
void expandImageBands(Scene& scene, uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

}  // namespace meso
