// Watertight tessellation of a limit surface with OpenSubdiv 3.5 Bfr::Tessellation and one rate per
// mesh edge, sharing the points of mesh vertices and edges between faces as in OpenSubdiv's
// tutorial_2_2 (shared/DESIGN.md section 5). tessellateUniform is the case of equal rates.
#include "meso/geometry/tessellation.h"

#include "face_split.h"
#include "limit_surface_impl.h"
#include "meso/core/check.h"
#include "meso/core/error.h"
#include "meso/core/huge_pages.h"
#include "meso/geometry/adaptive_tessellation.h"
#include "meso/geometry/ray_scene.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

namespace meso {

using OpenSubdiv::Bfr::Tessellation;
using OpenSubdiv::Far::ConstIndexArray;

EdgeRateTessellator::EdgeRateTessellator(const LimitSurface& surface, const std::vector<char>* keep)
    : surface_(surface),
      impl_(surface.impl()),
      base_(impl_.topology),
      vertexOwner_(base_.numVertices()),
      edgeOwner_(base_.numEdges()),
      vertexPoint_(base_.numVertices(), -1),
      edgePoint_(base_.numEdges(), -1) {
  // The first face in index order to reach a vertex or edge creates its points (tutorial_2_2).
  for (int f = 0; f < surface.numFaces(); ++f) {
    if (!surface.hasLimitSurface(f) || (keep && !(*keep)[f])) continue;
    faces_.push_back(f);
    const ConstIndexArray verts = base_.faceVertices(f);
    const ConstIndexArray edges = base_.faceEdges(f);
    for (int i = 0; i < verts.size(); ++i) {
      if (vertexOwner_[verts[i]].face < 0) vertexOwner_[verts[i]] = {.face = f, .corner = i};
      if (edgeOwner_[edges[i]].face < 0) edgeOwner_[edges[i]] = {.face = f, .corner = i};
    }
  }
  const size_t n = faces_.size();
  numPoints_.assign(n, 0);
  numFacets_.assign(n, 0);
  numGridOnly_.assign(n, 0);
  pointOffset_.assign(n + 1, 0);
  facetOffset_.assign(n + 1, 0);
}

Tessellation EdgeRateTessellator::faceTessellation(int face, const std::vector<int>& edgeRates,
                                                   FaceScratch& scratch) const {
  const ConstIndexArray edges = base_.faceEdges(face);
  scratch.rates.resize(edges.size());
  bool uniform = true;
  for (int i = 0; i < edges.size(); ++i) {
    scratch.rates[i] = edgeRates[edges[i]];
    uniform = uniform && scratch.rates[i] == scratch.rates[0];
  }
  Tessellation::Options options;
  options.SetFacetSize(3);
  const auto& param = impl_.faces[face].param;
  // Without explicit inner rates Bfr infers them: the mean of opposite edges' rates for quads, the
  // mean of all edge rates otherwise. Equal rates give the uniform pattern either way.
  if (uniform) return Tessellation(param, scratch.rates[0], options);
  return Tessellation(param, edges.size(), scratch.rates.data(), options);
}

size_t EdgeRateTessellator::ownedBoundaryPoints(int f, const std::vector<int>& edgeRates) const {
  size_t points = 0;
  const ConstIndexArray edges = base_.faceEdges(f);
  for (int i = 0; i < edges.size(); ++i) {
    const Use& v = vertexOwner_[base_.faceVertices(f)[i]];
    const Use& e = edgeOwner_[edges[i]];
    if (v.face == f && v.corner == i) ++points;
    if (e.face == f && e.corner == i) points += edgeRates[edges[i]] - 1;
  }
  return points;
}

size_t EdgeRateTessellator::countFacets(const std::vector<int>& edgeRates,
                                        const std::vector<FaceSplit>& splits) {
  MESO_DCHECK(edgeRates.size() == edgeOwner_.size(), "one rate per base edge");
  MESO_DCHECK(std::all_of(edgeRates.begin(), edgeRates.end(), [](int r) { return r >= 1; }),
              "every edge rate at least 1");
  MESO_DCHECK(splits.empty() || splits.size() == static_cast<size_t>(surface_.numFaces()),
              "one split per base face");
  tbb::parallel_for(tbb::blocked_range<size_t>(0, faces_.size(), 64),
                    [&](const tbb::blocked_range<size_t>& range) {
                      FaceScratch scratch;
                      for (size_t k = range.begin(); k != range.end(); ++k) {
                        const int f = faces_[k];
                        if (!splits.empty() && splits[f].split()) {
                          countSplitFace(k, edgeRates, splits[f], scratch);
                          continue;
                        }
                        const Tessellation tess = faceTessellation(f, edgeRates, scratch);
                        if (const int r = wholeGridRate(f, tess, scratch); r > 0) {
                          const size_t side = static_cast<size_t>(r) + 1;
                          numPoints_[k] = ownedBoundaryPoints(f, edgeRates) + side * side;
                          numGridOnly_[k] = gridsOnly_ ? 2 * size_t(r) * size_t(r) : 0;
                          numFacets_[k] = 2 * size_t(r) * size_t(r) - numGridOnly_[k];
                          continue;
                        }
                        numPoints_[k] = ownedBoundaryPoints(f, edgeRates) +
                                        static_cast<size_t>(tess.GetNumInteriorCoords());
                        numGridOnly_[k] = gridOnlyFacets(f, tess, scratch);
                        numFacets_[k] = static_cast<size_t>(tess.GetNumFacets()) - numGridOnly_[k];
                      }
                    });
  size_t gridOnly = 0;
  for (size_t k = 0; k < faces_.size(); ++k) {
    pointOffset_[k + 1] = pointOffset_[k] + numPoints_[k];
    facetOffset_[k + 1] = facetOffset_[k] + numFacets_[k];
    gridOnly += numGridOnly_[k];
  }
  return facetOffset_.back() + gridOnly;
}

// The face's points come in Bfr's boundary order (vertex 0, the points of edge 0, vertex 1, ...),
// then its interior, so equal rates reproduce the first-come numbering of a sequential walk.
void EdgeRateTessellator::layoutOwnedPoints(size_t k, const std::vector<int>& edgeRates) {
  const int f = faces_[k];
  const ConstIndexArray verts = base_.faceVertices(f);
  const ConstIndexArray edges = base_.faceEdges(f);
  size_t next = pointOffset_[k];
  for (int i = 0; i < verts.size(); ++i) {
    const Use& v = vertexOwner_[verts[i]];
    if (v.face == f && v.corner == i) vertexPoint_[verts[i]] = static_cast<int>(next++);
    const Use& e = edgeOwner_[edges[i]];
    if (e.face == f && e.corner == i) {
      edgePoint_[edges[i]] = static_cast<int>(next);
      next += edgeRates[edges[i]] - 1;
    }
  }
}

// Bfr's boundary coordinates run vertex 0, the points of edge 0, vertex 1, ... Edge points are
// stored from the lower to the higher mesh vertex index, whichever way a face runs along the edge.
void EdgeRateTessellator::placeBoundary(size_t k, const std::vector<int>& edgeRates,
                                        FaceScratch& scratch) {
  const int f = faces_[k];
  const ConstIndexArray verts = base_.faceVertices(f);
  const ConstIndexArray edges = base_.faceEdges(f);
  int b = 0;
  for (int i = 0; i < verts.size(); ++i) {
    const Use& v = vertexOwner_[verts[i]];
    if (v.face == f && v.corner == i)
      samples_[vertexPoint_[verts[i]]] = {.face = f, .st = scratch.st[b]};
    scratch.point[b++] = vertexPoint_[verts[i]];
    const int n = edgeRates[edges[i]] - 1;
    const bool forward = verts[i] < verts[(i + 1) % verts.size()];
    const int first = edgePoint_[edges[i]];
    const Use& e = edgeOwner_[edges[i]];
    for (int j = 0; j < n; ++j) {
      const int point = first + (forward ? j : n - 1 - j);
      if (e.face == f && e.corner == i) samples_[point] = {.face = f, .st = scratch.st[b]};
      scratch.point[b++] = point;
    }
  }
}

// The interior coordinates of a quad face are the (innerU - 1) x (innerV - 1) points (i / innerU,
// j / innerV) of a regular grid (Bfr lists them ring by ring), with Bfr's inferred inner rates.
EdgeRateTessellator::GridShape EdgeRateTessellator::interiorGrid(int face, const Tessellation& tess,
                                                                 const FaceScratch& scratch) const {
  GridShape shape;
  if (impl_.faces[face].param.GetType() != OpenSubdiv::Bfr::Parameterization::QUAD) return shape;
  const std::vector<int>& r = scratch.rates;
  const bool uniform = tess.IsUniform();
  // Explicit inner rates follow the edge rates (split faces' sub-quads), else Bfr infers them.
  const bool inner = r.size() == 6;
  shape.innerU = uniform ? r[0] : inner ? r[4] : (r[0] + r[2]) / 2;
  shape.innerV = uniform ? r[0] : inner ? r[5] : (r[1] + r[3]) / 2;
  const int width = shape.innerU - 1, height = shape.innerV - 1;
  if (width < 2 || height < 2 || tess.GetNumInteriorCoords() != width * height) return {};
  shape.width = width;
  shape.height = height;
  return shape;
}

int EdgeRateTessellator::wholeGridRate(int face, const Tessellation& tess,
                                       const FaceScratch& scratch) const {
  if (!wholeGrids_ || !tess.IsUniform() || scratch.rates.size() != 4 ||
      impl_.faces[face].param.GetType() != OpenSubdiv::Bfr::Parameterization::QUAD)
    return 0;
  const int r = scratch.rates[0];
  // Embree grids are at most 32767 points a side; Bfr's uniform quad has 2 r^2 triangles.
  return r >= 1 && r < 32767 && tess.GetNumFacets() == 2 * r * r ? r : 0;
}

size_t EdgeRateTessellator::gridOnlyFacets(int face, const Tessellation& tess,
                                           const FaceScratch& scratch) const {
  if (!gridsOnly_) return 0;
  const GridShape shape = interiorGrid(face, tess, scratch);
  return shape.width > 0 ? 2 * size_t(shape.width - 1) * size_t(shape.height - 1) : 0;
}

namespace {

// Facets keep the corners' st in their own face; corners are ordered counter-clockwise in st,
// which is the orientation of the limit normal (dP/ds x dP/dt).
void writeTriangle(TessellatedMesh& out, size_t t, int face, int c0, int c1, int c2,
                   const std::vector<int>& point, const std::vector<Vec2>& st, bool orient) {
  int c[3] = {c0, c1, c2};
  const Vec2 e1 = st[c[1]] - st[c[0]], e2 = st[c[2]] - st[c[0]];
  if (orient && e1.x * e2.y - e1.y * e2.x < 0.0f) std::swap(c[1], c[2]);
  for (int j = 0; j < 3; ++j) {
    out.indices[3 * t + j] = static_cast<uint32_t>(point[c[j]]);
    out.cornerSt[3 * t + j] = st[c[j]];
  }
  out.triangleFace[t] = face;
}

// The cells of a width x height grid of coordinates (`coord`, row by row), two triangles a cell
// split as Embree splits grid cells (TriangleGrid), from triangle t on; returns the next triangle.
size_t writeGridCells(TessellatedMesh& out, size_t t, int face, const std::vector<int>& coord,
                      int width, int height, const std::vector<int>& point,
                      const std::vector<Vec2>& st) {
  for (int v = 0; v + 1 < height; ++v)
    for (int u = 0; u + 1 < width; ++u) {
      const int p00 = coord[v * width + u], p10 = coord[v * width + u + 1];
      const int p01 = coord[(v + 1) * width + u], p11 = coord[(v + 1) * width + u + 1];
      writeTriangle(out, t++, face, p00, p10, p01, point, st, false);
      writeTriangle(out, t++, face, p11, p01, p10, point, st, false);
    }
  return t;
}

// The grid's face and its st corners (TriangleGrid), when every grid point's st is their bilinear
// blend to 10% of the grid's smaller step in st, or 4e-6. Interior grids of quads are bilinear, in
// Bfr's coordinates and in the split faces' sub-quads, whose corners need not form a rectangle, up
// to Bfr's own float spacing of its points: measured up to 1% of a step, along rows of 2000
// points at grazing views, 0.13% of a row between the rows of quads with explicit inner rates, and
// 5.0% of a step in a grid of 1570 x 2064 points (scenes/horizon.toml displaced at 320x180). A
// hit's st is then off by as little, far below a pixel. Returns whether they are; one grid that is
// not makes its whole surface store every triangle (about 2.3 times the geometry memory).
bool setGridPatchCoords(int face, const std::vector<int>& coord, const std::vector<Vec2>& st,
                        TriangleGrid& grid) {
  const int width = grid.width, height = grid.height;
  const size_t w = size_t(width), last = size_t(height - 1) * w;
  TriangleGrid g = grid;
  g.cornerSt = {st[coord[0]], st[coord[w - 1]], st[coord[last]], st[coord[last + w - 1]]};
  const float step = std::min(glm::length(g.cornerSt[1] - g.cornerSt[0]) / float(width - 1),
                              glm::length(g.cornerSt[2] - g.cornerSt[0]) / float(height - 1));
  const float tolerance = std::max(4e-6f, 0.1f * step);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const Vec2 d = st[coord[size_t(j) * w + size_t(i)]] - g.stAt(i, j);
      if (!(std::abs(d.x) <= tolerance && std::abs(d.y) <= tolerance)) return false;
    }
  g.face = face;
  grid = g;
  return true;
}

}  // namespace

// scratch.coords, .st and .point sized for the points of the face's pattern `tess` (only its
// boundary points when boundaryOnly), and its boundary points placed (placeBoundary).
void EdgeRateTessellator::beginFace(size_t k, const Tessellation& tess,
                                    const std::vector<int>& edgeRates, bool boundaryOnly,
                                    FaceScratch& scratch) {
  const int f = faces_[k];
  const int count = boundaryOnly ? tess.GetNumBoundaryCoords() : tess.GetNumCoords();
  scratch.coords.resize(2 * static_cast<size_t>(count));
  if (boundaryOnly)
    tess.GetBoundaryCoords(scratch.coords.data());
  else
    tess.GetCoords(scratch.coords.data());
  scratch.st.resize(count);
  for (int j = 0; j < count; ++j)
    scratch.st[j] = impl_.bfrToChart(f, Vec2(scratch.coords[2 * j], scratch.coords[2 * j + 1]));
  scratch.point.resize(count);
  placeBoundary(k, edgeRates, scratch);
}

// Creates the samples of the points this face owns and its triangles.
void EdgeRateTessellator::emitFace(size_t k, const std::vector<int>& edgeRates,
                                   FaceScratch& scratch, TessellatedMesh& out, TriangleGrid* grid) {
  const Tessellation tess = faceTessellation(faces_[k], edgeRates, scratch);
  beginFace(k, tess, edgeRates, false, scratch);
  if (const int r = wholeGridRate(faces_[k], tess, scratch); r > 0) {
    emitWholeGrid(k, r, scratch, out, grid);
    return;
  }
  const int interiorBase = static_cast<int>(pointOffset_[k + 1]) - tess.GetNumInteriorCoords();
  emitPattern(faces_[k], tess, scratch, interiorBase, facetOffset_[k], out, grid);
}

// With `grid`, interior points are stored row by row and the interior cells are triangulated last,
// two triangles a cell split as Embree splits grid cells (see TriangleGrid); they are
// counter-clockwise in st by construction. scratch.rates are the pattern's edge rates.
size_t EdgeRateTessellator::emitPattern(int f, const Tessellation& tess, FaceScratch& scratch,
                                        int interiorBase, size_t t, TessellatedMesh& out,
                                        TriangleGrid* grid) {
  const int numCoords = tess.GetNumCoords(), numBoundary = tess.GetNumBoundaryCoords();
  const GridShape shape = grid ? interiorGrid(f, tess, scratch) : GridShape{};
  scratch.gridCoord.assign(static_cast<size_t>(shape.width) * shape.height, -1);
  for (int j = numBoundary; j < numCoords; ++j) {
    int slot = j - numBoundary;
    if (shape.width > 0) {
      const int u = static_cast<int>(std::lround(scratch.coords[2 * j] * shape.innerU)) - 1;
      const int v = static_cast<int>(std::lround(scratch.coords[2 * j + 1] * shape.innerV)) - 1;
      slot = v * shape.width + u;
      scratch.gridCoord[slot] = j;
    }
    scratch.point[j] = interiorBase + slot;
    samples_[scratch.point[j]] = {.face = f, .st = scratch.st[j]};
  }

  scratch.facets.resize(3 * static_cast<size_t>(tess.GetNumFacets()));
  tess.GetFacets(scratch.facets.data());
  for (size_t q = 0; q < scratch.facets.size(); q += 3) {
    const int* c = &scratch.facets[q];
    if (shape.width > 0 && c[0] >= numBoundary && c[1] >= numBoundary && c[2] >= numBoundary)
      continue;  // an interior cell: written below in grid order
    writeTriangle(out, t++, f, c[0], c[1], c[2], scratch.point, scratch.st, true);
  }
  if (shape.width == 0) return t;
  return emitGrid(f, static_cast<size_t>(interiorBase), shape.width, shape.height, t, scratch, out,
                  grid);
}

// With gridsOnly_ hits in the grid take their face and st from it alone, so it must know them.
size_t EdgeRateTessellator::emitGrid(int f, size_t firstVertex, int width, int height, size_t t,
                                     FaceScratch& scratch, TessellatedMesh& out,
                                     TriangleGrid* grid) const {
  *grid = {static_cast<uint32_t>(firstVertex), static_cast<uint32_t>(t),
           static_cast<uint16_t>(width), static_cast<uint16_t>(height)};
  const std::vector<int>& g = scratch.gridCoord;
  const bool known = setGridPatchCoords(f, g, scratch.st, *grid);
  if (gridsOnly_) {
    if (!known)
      throw NotBilinearGrid("the grid of face " + std::to_string(f) +
                            " is not bilinear in its patch coordinates");
    grid->firstTriangle = TriangleGrid::kNotInMesh;
    return t;
  }
  return writeGridCells(out, t, f, g, width, height, scratch.point, scratch.st);
}

// The uniform pattern's coordinates are the points (i / r, j / r): slot j (r + 1) + i of the
// face's block. Interior points are evaluated there; border slots copy the shared point the
// boundary placed (evaluated once, by the face that owns it), so the grid's border is bit for bit
// its neighbours' and the surface stays watertight.
size_t EdgeRateTessellator::emitWholeGrid(size_t k, int rate, FaceScratch& scratch,
                                          TessellatedMesh& out, TriangleGrid* grid) {
  const int f = faces_[k];
  const int side = rate + 1;
  const size_t base = pointOffset_[k + 1] - size_t(side) * size_t(side);
  const int numCoords = static_cast<int>(scratch.st.size());
  const int numBoundary = 4 * rate;
  scratch.gridCoord.assign(size_t(side) * size_t(side), -1);
  for (int j = 0; j < numCoords; ++j) {
    const int u = static_cast<int>(std::lround(scratch.coords[2 * j] * rate));
    const int v = static_cast<int>(std::lround(scratch.coords[2 * j + 1] * rate));
    const size_t slot = size_t(v) * size_t(side) + size_t(u);
    scratch.gridCoord[slot] = j;
    if (j >= numBoundary) {
      scratch.point[j] = static_cast<int>(base + slot);
      samples_[base + slot] = {.face = f, .st = scratch.st[j]};
    } else {
      samples_[base + slot] = {.face = f, .st = scratch.st[j], .copyOf = scratch.point[j]};
    }
  }
  MESO_DCHECK(
      std::none_of(scratch.gridCoord.begin(), scratch.gridCoord.end(), [](int c) { return c < 0; }),
      "a uniform quad's pattern fills its grid");
  // The mesh's triangles (without gridsOnly_) use the shared border points, so the mesh alone is
  // watertight too.
  return emitGrid(f, base, side, side, facetOffset_[k], scratch, out, grid);
}

void EdgeRateTessellator::evaluatePoints(const VertexDisplacement* displacement,
                                         TessellatedMesh& out) const {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, samples_.size(), 256),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const Sample& s = samples_[i];
                        if (s.copyOf >= 0) continue;
                        const SurfacePoint sp = surface_.evaluate(s.face, s.st);
                        out.positions[i] =
                            displacement ? sp.P + displacement->offset(s.face, s.st, sp) : sp.P;
                      }
                    });
}

TessellatedMesh EdgeRateTessellator::tessellate(const std::vector<int>& edgeRates,
                                                const VertexDisplacement* displacement,
                                                std::vector<TriangleGrid>* grids,
                                                const std::vector<FaceSplit>& splits) {
  if (!grids) gridsOnly_ = false;  // without grids every triangle is stored
  wholeGrids_ = grids != nullptr;  // counts the same triangles, more points
  const size_t numFacets = countFacets(edgeRates, splits);
  const size_t numStored = facetOffset_.back();
  const size_t numPoints = pointOffset_.back();
  if (numPoints > static_cast<size_t>(INT32_MAX))
    throw Error("tessellation needs " + std::to_string(numPoints) +
                " points, more than 32-bit indices address");
  tbb::parallel_for(size_t(0), faces_.size(), [&](size_t k) { layoutOwnedPoints(k, edgeRates); });
  TessellatedMesh out;
  out.gridOnlyTriangles = numFacets - numStored;
  // The large buffers' pages are mapped on both cores before their serial resize.
  resizePopulated(out.indices, 3 * numStored);
  resizePopulated(out.cornerSt, 3 * numStored);
  resizePopulated(out.triangleFace, numStored);
  resizePopulated(samples_, numPoints);
  // Split faces have one grid per sub-quad; empty vectors cost no allocation.
  std::vector<TriangleGrid> faceGrids(grids ? faces_.size() : 0);
  std::vector<std::vector<TriangleGrid>> splitGrids(grids && !splits.empty() ? faces_.size() : 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, faces_.size(), 16),
                    [&](const tbb::blocked_range<size_t>& range) {
                      FaceScratch scratch;
                      for (size_t k = range.begin(); k != range.end(); ++k) {
                        if (!splits.empty() && splits[faces_[k]].split())
                          emitSplitFace(k, edgeRates, splits[faces_[k]], scratch, out,
                                        grids ? &splitGrids[k] : nullptr);
                        else
                          emitFace(k, edgeRates, scratch, out, grids ? &faceGrids[k] : nullptr);
                      }
                    });
  if (grids) {
    grids->clear();
    for (size_t k = 0; k < faceGrids.size(); ++k) {
      if (faceGrids[k].width > 0) grids->push_back(faceGrids[k]);
      if (!splitGrids.empty())
        grids->insert(grids->end(), splitGrids[k].begin(), splitGrids[k].end());
    }
  }
  // With grids alone holding the grids' triangles, room for RayScene::takeMesh to put the other
  // triangles' points after these: 4 each, and one more.
  resizePopulated(out.positions, numPoints, gridsOnly_ ? 4 * numStored + 1 : 0);
  evaluatePoints(displacement, out);
  tbb::parallel_for(size_t(0), samples_.size(), [&](size_t i) {
    if (samples_[i].copyOf >= 0) out.positions[i] = out.positions[samples_[i].copyOf];
  });
  std::vector<Sample>().swap(samples_);  // the caller keeps the mesh, not the samples
  return out;
}

TessellatedMesh tessellateUniform(const LimitSurface& surface, int rate) {
  if (rate < 1)
    throw Error("tessellation rate must be at least 1 (got " + std::to_string(rate) + ")");
  EdgeRateTessellator tessellator(surface);
  return tessellator.tessellate(std::vector<int>(tessellator.numEdges(), rate), nullptr);
}

}  // namespace meso
