// A metric class's visible-normal histograms and self-shadowing factor from those of one traced
// tile of the same relief level (docs/metric.md, docs/tables.md): tracing grows with relief levels,
// not with metric classes.
#pragma once

#include "meso/appearance/class_map.h"
#include "meso/appearance/shadowing_table.h"
#include "meso/appearance/visible_normal_histogram.h"

namespace meso {

// The histogram a class of map `map` would trace with `resolution` and `azimuths` view azimuths
// (HistogramSettings), from the tile's histogram `tile` (identity shape, view-azimuth slices). An
// affine map keeps orthographic projection and occlusion, so the class's visible normals seen
// from V are the tile's seen from V' = M^-1 V, each mapped by M^-T, with the same relative
// weights (projected areas all scale by one constant). At each traced azimuth the tile's slices
// around V' are interpolated (as the renderers interpolate them), and each bin's mass is split
// over sub-bin samples that are mapped one by one, as many as the map stretches bins, so that
// rebinning spreads a bin's mass over the class's bins it covers instead of dropping it in one.
// Deterministic whatever the thread count (slices are independent).
VisibleNormalHistogram deriveHistogram(const VisibleNormalHistogram& tile, const ClassMap& map,
                                       const HistogramResolution& resolution, int azimuths);

// The self-shadowing factor of the class on the nodes of `layout` (the class's histogram):
// at (V, L) the tile's at (M^-1 V, M^-1 L). Which points are seen and lit is exactly the tile's;
// the factor's weights, (L.n)+ and (H.n)+^phong over the visible hits, are not: L.n in the class
// is the tile's L'.n' times |M^-1 L| / |M^-T n'|, a factor that varies over the hits (and H does
// not map to H'), so the factor is the tile's to the extent that the weights' change is
// uncorrelated with being lit (measured in docs/tables.md).
// Only on the theta_V rows `rows` of the layout (ShadowingTable::tabulate).
ShadowingTable deriveShadowing(const ShadowingTable& tile, const ClassMap& map,
                               const VisibleNormalHistogram& layout, ShadowingResolution res,
                               ViewRows rows = {});

}  // namespace meso
