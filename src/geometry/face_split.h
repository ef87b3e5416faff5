// Private to src/geometry: quad faces whose interior is split into sub-quads where the dicing rate
// changes across them, as DiagSplit splits patches (Fisher et al. 2009, "DiagSplit: parallel,
// crack-free, adaptive tessellation for micropolygon rendering"). Mesh edges keep one rate each
// and their shared points, so splitting stays inside a face and cannot crack the mesh.
#pragma once

#include "cap_coarsening.h"
#include "meso/geometry/adaptive_tessellation.h"

#include <cstddef>
#include <vector>

namespace meso {

// Most sub-quads along u or v of one face (16: a face much larger than the view, near the eye,
// keeps its diced part within a sixteenth of the face).
inline constexpr int kMaxSplit = 16;

// How one quad face is split for given edge rates: nu x nv sub-quads (powers of two, nu at most the
// rates of edges 0 and 2, nv those of edges 1 and 3); 1 x 1 is the whole face, diced as before.
struct FaceSplit {
  int nu = 1, nv = 1;
  // Segments each sub-quad asks for along u and along v (index j * nu + i): a split line between
  // two sub-quads gets the larger of their asks, so neither is diced coarser than it asked.
  std::vector<int> askU, askV;
  bool split() const { return nu * nv > 1; }
};

// The sub-quads of a split face for its edge rates R[0..3]. Split lines end on points the mesh
// edges already have: column i meets edge 0 at its point round(i R0 / nu) and edge 2 where
// u = round(i R2 / nu) / R2, and likewise rows on edges 1 and 3 (Bfr's boundary runs edge 0 along
// +u, 1 along +v, 2 along -u, 3 along -v). Indices below are along each edge in Bfr's direction.
struct SplitPattern {
  int nu = 1, nv = 1;
  int R[4] = {1, 1, 1, 1};
  int bottom[kMaxSplit + 1] = {}, top[kMaxSplit + 1] = {};  // column i on edges 0 and 2
  int right[kMaxSplit + 1] = {}, left[kMaxSplit + 1] = {};  // row j on edges 1 and 3
  std::vector<int> rowRate, colRate;    // row j (1..nv-1) segment i at (j-1) nu + i; column i
                                        // (1..nu-1) segment j at (i-1) nv + j
  std::vector<int> rowFirst, colFirst;  // first owned point of each segment (after the crossings)
  int numCrossings = 0;                 // (nu - 1)(nv - 1) points where split lines cross
  int numLinePoints = 0;                // crossings plus the points inside split-line segments

  std::vector<int> askU, askV;  // FaceSplit's

  // Rates of sub-quad (i, j) for Bfr: its four edges in Bfr order (bottom, right, top, left), then
  // its inner rates along u and v, which are its own asks. Bfr would infer the mean of opposite
  // edges, which keeps a sub-quad beside a finely diced mesh edge (diced for the face's densest
  // part) half as fine as that edge even where it lies out of view.
  void subRates(int i, int j, int r[6]) const;
};

SplitPattern splitPattern(const int R[4], const FaceSplit& split);

// What the cells of a face's split grid measured once (planSplits); rates for any coarsening and
// edge rates follow (splitsFor).
struct SplitPlan {
  struct Cell {
    bool diced = false;  // in view and near enough to raise relief (FaceDicing::raisesBox)
    float lengthU = 0.0f, lengthV = 0.0f;  // pixel lengths by DicingSettings::metric
    float coarseU = 0.0f, coarseV = 0.0f;  // segments following the limit surface to tolerance
    // From the eye to the box of its samples grown as for `diced` (a lower bound of the distance
    // of its displaced surface); a sub-quad is coarsened by the cap as its nearest cell.
    float distance = 0.0f;
    // Shares of the texel cap along u and v (acrossViewCapScale at the cell's centre).
    float capScaleU = 1.0f, capScaleV = 1.0f;
  };
  struct Face {
    int nu = 1, nv = 1;  // cells along u and v; 1 x 1: never split
    size_t firstCell = 0;
    int cap = 0, floor = 0;  // the face's texel cap and floor (rates per whole edge)
  };
  std::vector<Face> faces;  // per base face
  std::vector<Cell> cells;  // row by row within each face
};

// Cells of the diced quad faces in view whose parts differ: some part out of view or too far to
// raise relief (FaceDicing::raiseDistance), or pixel densities more than kSplitDensityRatio apart.
// `bound` is the displacement bound.
SplitPlan planSplits(const LimitSurface& surface, const ScreenMetric& screen,
                     const DicingSettings& settings, const FaceDicing& faces,
                     const std::vector<char>& inView, float bound);

// The largest distance of a cell (0 without cells).
float farthestCell(const SplitPlan& plan);

// The splits for the given edge rates and cap coarsening (empty when no face splits); each
// sub-quad is coarsened by cap.factor of its nearest cell's distance. `facesSplit` counts the
// faces split.
std::vector<FaceSplit> splitsFor(const LimitSurface& surface, const SplitPlan& plan,
                                 const std::vector<int>& edgeRates, const DicingSettings& settings,
                                 const CapCoarsening& cap, int& facesSplit);

}  // namespace meso
