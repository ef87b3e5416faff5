// Faces whose limit surface two triangles draw exactly, and the tessellation of objects drawn
// undisplaced that spends triangles only on the others.
#pragma once

#include "meso/core/memory_budget.h"
#include "meso/geometry/limit_surface.h"
#include "meso/geometry/tessellation.h"

#include <cstdint>
#include <string>
#include <vector>

namespace meso {

// Per face: 1 where the limit surface is an affine image of the face's patch coordinates (a flat
// parallelogram of a bilinear mesh, such as every face of a ground grid), to 1e-5 of the face's
// size plus 8 units in the last place of its largest coordinate, at its corners, edge midpoints
// and interior points. Such a face's
// triangles lie in its surface, and a hit's barycentrics give exactly the patch coordinates of the
// limit point it hit, at any tessellation rate.
std::vector<uint8_t> affineFaces(const LimitSurface& surface);
// affineFaces' entry of one face with a limit surface.
bool faceIsAffine(const LimitSurface& surface, int face);

// tessellateUniform at `rate`, except that edges whose every face is affine get one segment: a
// flat ground of 8 x 8-unit faces is 2 triangles a face instead of 2 rate^2, and curved faces (and
// the edges they share with flat ones) keep `rate`. The same surface in view as tessellateUniform
// up to rounding. Refused (meso::Error naming `where` and render.tessellation_rate) before any
// triangle is made when its triangles, at kBytesPerMicropolygon each, beside `heldBytes` already
// held (film, tables, limit surfaces), would exceed `memoryLimitBytes` (--memory-limit).
// `affine`: affineFaces(surface) when the caller has it (null: computed here).
TessellatedMesh tessellateSmooth(const LimitSurface& surface, int rate,
                                 uint64_t memoryLimitBytes = defaultMemoryLimitBytes(),
                                 const std::string& where = "", double heldBytes = 0.0,
                                 const std::vector<uint8_t>* affine = nullptr);

}  // namespace meso
