// Private to src/geometry: what LimitSurface prepares per base face, shared with the tessellators.
#pragma once

#include "face_split.h"
#include "meso/geometry/limit_surface.h"
#include "meso/geometry/tessellation.h"

#include <opensubdiv/bfr/parameterization.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <vector>

namespace meso {

// meso's patch coordinates st equal Bfr's (u, v) for quads (unit square). A Loop triangle's st
// lives on the chart triangle below, of which Bfr's (u, v) are the barycentric coordinates. Bfr
// parameterizes every other face (triangles and N-gons under Catmull-Clark or bilinear) by N quad
// sub-faces laid out as disjoint tiles, so a triangle of Bfr's tessellation can have corners in
// different tiles and interpolating their coordinates would be meaningless. For those faces meso's
// st lives in a continuous chart instead: for N = 3 the
// control triangle's own shape (scaled to area one half), a regular N-gon inscribed in the unit
// square otherwise. Sub-face i is the kite (V_i, M_i, C, M_i-1) of the chart, mapped bilinearly
// onto the sub-face's normalized square, so the map is continuous and orientation preserving, and
// a flat triangle under the bilinear scheme (whose sub-faces are the bilinear patches of the same
// kites in space) is a similar image of its chart: its relief is undistorted, isotropic, of one
// metric class.
// Appends the chart vertices of an N-gon face (`corners`: its control points, read for N = 3),
// counter-clockwise from edge 0 along +s, then the centre. Defined in face_chart.cpp with
// Impl::chartToBfr and Impl::bfrToChart.
void appendFaceChart(int n, const Vec3* corners, std::vector<Vec2>& chart);

struct LimitSurface::Impl {
  // Per base face. A bilinear quad (the faces of a ground grid) keeps no Bfr surface (128 bytes
  // each, for positions and for uv): it is evaluated from its 4 patch points alone. Faces of a
  // chunk whose regular patches have the same basis share one (storeSurface, limit_surface.cpp).
  struct Face {
    OpenSubdiv::Bfr::Parameterization param;
    int numPatchPoints = 0;  // 0: the face has no limit surface (a hole or non-manifold face)
    // Offsets in the arrays of the face's chunk (Chunk, below). Index in `surfaces` of the Bfr
    // surfaces of the positions and of the face-varying (u, v); -1 where the patch is bilinear
    // (below) or, for uv, where the mesh has none.
    int surface = -1, uvSurface = -1;
    int patchOffset = 0;  // first float of this face's patch points
    int uvPatchOffset = 0;
    int chartOffset =
        -1;  // first chart point (N vertices, then the centre); -1: st is Bfr's (quads)
    // The patch is the bilinear quad of its 4 patch points (quads of the bilinear scheme: set up
    // from their corners, or, next to a non-manifold component, checked against Bfr when the
    // surface is made): evaluated directly, without Bfr's generic basis and point combination
    // (the hybrid's shading evaluates the limit surface at every hit).
    bool bilinear = false, uvBilinear = false;
    bool hasUv = false;  // the face has face-varying (u, v)
    // The patch points are control points (a regular or linear patch): patchOffset is the first of
    // their indices in the chunk's controlIndices, not a float of its patchPoints; -1 for a quad
    // whose patch points are its 4 vertices (a plain bilinear quad), read from the topology.
    bool gathered = false;
    bool valid() const { return numPatchPoints > 0; }
  };

  // The base level's relations the tessellators use, in OpenSubdiv's numbering of vertices and
  // edges, copied from the refiner, which is released once the surfaces are made: it holds every
  // relation of every component (about 220 bytes a quad face), these about 50.
  struct Topology {
    using Indices = OpenSubdiv::Far::ConstIndexArray;
    int vertices = 0;
    std::vector<int> faceFirst;             // per face, then the corner count: its first corner
    std::vector<int> faceVertex, faceEdge;  // per corner
    std::vector<int> edgeFirst;             // per edge, then the count of edge-face incidences
    std::vector<int> edgeFace;
    int numVertices() const { return vertices; }
    int numEdges() const { return static_cast<int>(edgeFirst.size()) - 1; }
    Indices faceVertices(int f) const {
      return Indices(faceVertex.data() + faceFirst[f], faceFirst[f + 1] - faceFirst[f]);
    }
    Indices faceEdges(int f) const {
      return Indices(faceEdge.data() + faceFirst[f], faceFirst[f + 1] - faceFirst[f]);
    }
    Indices edgeFaces(int e) const {
      return Indices(edgeFace.data() + edgeFirst[e], edgeFirst[e + 1] - edgeFirst[e]);
    }
    size_t memoryBytes() const;
  };

  // The arrays of kFacesPerChunk consecutive faces, prepared in parallel and kept as made: one
  // array of each for the whole surface would have to be joined from them, holding both at once.
  static constexpr int kFacesPerChunk = 1024;
  struct Chunk {
    std::vector<OpenSubdiv::Bfr::Surface<float>> surfaces;  // of faces that are not bilinear
    std::vector<float> patchPoints;                         // 3 floats per point
    std::vector<int> controlIndices;   // of the patch points of faces that gather them
    std::vector<float> uvPatchPoints;  // 2 floats per point
    std::vector<Vec2> chartPoints;
    size_t memoryBytes() const;
  };

  Topology topology;
  std::vector<Face> faces;
  std::vector<Chunk> chunks;
  // The mesh's points, gathered by index into the patch points of most faces: 16 indices a regular
  // Catmull-Clark face (64 bytes) instead of 16 points (192), 4 a bilinear quad (16, not 48).
  std::vector<Vec3> controlPoints;
  static constexpr int kMaxGathered = 16;  // most patch points a face gathers

  const Chunk& chunkOf(int face) const {
    return chunks[static_cast<size_t>(face) / kFacesPerChunk];
  }
  // The face's patch points (3 floats each): its own, or its control points gathered into
  // `buffer` (room for kMaxGathered points).
  const float* patchPoints(int face, float* buffer) const {
    const Face& f = faces[face];
    const Chunk& chunk = chunkOf(face);
    if (!f.gathered) return &chunk.patchPoints[f.patchOffset];
    const int* index = f.patchOffset < 0 ? &topology.faceVertex[topology.faceFirst[face]]
                                         : &chunk.controlIndices[f.patchOffset];
    for (int k = 0; k < f.numPatchPoints; ++k) {
      const Vec3& p = controlPoints[index[k]];
      buffer[3 * k] = p.x, buffer[3 * k + 1] = p.y, buffer[3 * k + 2] = p.z;
    }
    return buffer;
  }
  const float* uvPatchPoints(int face) const {
    return &chunkOf(face).uvPatchPoints[faces[face].uvPatchOffset];
  }
  const Vec2* chartPoints(int face) const {
    return &chunkOf(face).chartPoints[faces[face].chartOffset];
  }

  // Centroid and Newell normal of the face's control polygon, from its vertices when asked (rarely:
  // the point and normal of a face without a limit surface, the normal where the limit normal is
  // undefined).
  void polygonFrame(int face, Vec3& centroid, Vec3& normal) const;

  // Bfr coordinates of meso's st (clamped into the face) and their Jacobian d(Bfr uv)/d(st).
  Vec2 chartToBfr(int face, Vec2 st, glm::mat2& jacobian) const;
  // meso's st of a point given in Bfr coordinates.
  Vec2 bfrToChart(int face, Vec2 bfrUv) const;
  // meso's st of corner `corner` of the face: the edge from corner i to corner i + 1 is the
  // straight st segment between them (in the chart too, whose boundary maps onto the face's edges).
  Vec2 cornerSt(int face, int corner) const {
    const Face& f = faces[face];
    if (f.chartOffset >= 0) return chartPoints(face)[corner];
    Vec2 uv;
    f.param.GetVertexCoord(corner, &uv.x);
    return uv;
  }
};

class VertexDisplacement;  // meso/geometry/adaptive_tessellation.h
struct TriangleGrid;       // meso/geometry/ray_scene.h

// The engine behind tessellateUniform and tessellateAdaptive (tessellation.cpp): Bfr tessellation
// with one rate per base-level edge (OpenSubdiv's edge numbering). A rate is a property of the
// edge, so both faces of an edge place the same points on it; those points, like the corner points,
// are created once by the first face (in index order) that reaches them and shared by the others,
// as in OpenSubdiv's tutorial_2_2, so the mesh is watertight. The point layout depends on the rates
// only (faces are laid out by prefix sums, not by which thread gets there first), so the output is
// the same whatever the number of threads.
class EdgeRateTessellator {
 public:
  // `keep` (one entry per base face; null: every face): the faces to tessellate; the others get no
  // points or triangles, and the kept faces share points among themselves alone.
  explicit EdgeRateTessellator(const LimitSurface& surface,
                               const std::vector<char>* keep = nullptr);

  // Where a face first reaches a mesh vertex or edge: that face creates the output points there.
  struct Use {
    int face = -1;  // -1: no face with a limit surface uses it
    int corner = 0;
  };
  int numEdges() const { return static_cast<int>(edgeOwner_.size()); }
  const Use& edgeOwner(int edge) const { return edgeOwner_[edge]; }

  // With grids only (tessellate with `grids`), the triangles of the interior grids are not stored
  // in the mesh's per-triangle arrays (TriangleGrid::kNotInMesh, DicingSettings::gridsOnly).
  // tessellate then throws NotBilinearGrid when a grid's patch coordinates are not bilinear over
  // it (a degenerate chart), so that the caller can tessellate again without.
  void setGridsOnly(bool gridsOnly) { gridsOnly_ = gridsOnly; }
  struct NotBilinearGrid : std::runtime_error {
    using std::runtime_error::runtime_error;
  };
  // Triangles the given rates produce (every rate >= 1), from Bfr's pattern counts alone, those of
  // grids only included. `splits` (per base face, or empty: none) splits the interiors of quad
  // faces (face_split.h).
  size_t countFacets(const std::vector<int>& edgeRates, const std::vector<FaceSplit>& splits = {});
  // The mesh. Each output point is evaluated on the limit surface and, with a displacement, moved
  // by its offset once (in the face that created it). With `grids`, the interior points of each
  // quad face are stored row by row and its interior cells triangulated as Embree's grids are,
  // and each such block is listed in *grids (faces in index order); without, points and triangles
  // come in Bfr's order.
  // Split faces list one grid per sub-quad interior.
  TessellatedMesh tessellate(const std::vector<int>& edgeRates,
                             const VertexDisplacement* displacement,
                             std::vector<TriangleGrid>* grids = nullptr,
                             const std::vector<FaceSplit>& splits = {});

 private:
  struct Sample {
    int face;
    Vec2 st;
    int copyOf = -1;  // >= 0: not evaluated, a copy of that point (a whole-face grid's border)
  };
  // Buffers of one task, reused from face to face.
  struct FaceScratch {
    std::vector<int> rates;      // of the face's (or sub-quad's) edges
    std::vector<float> coords;   // Bfr (u, v) pairs: boundary first, then interior
    std::vector<int> facets;     // 3 coordinate indices per triangle
    std::vector<Vec2> st;        // meso's st of each coordinate
    std::vector<int> point;      // output point of each coordinate
    std::vector<int> gridCoord;  // coordinate at each interior grid slot, row by row
    // Split faces: the face's boundary (point, st), its split-grid nodes (Bfr uv), and the points
    // and st of its split lines (crossings first, then the segments' inner points).
    std::vector<int> facePoint;
    std::vector<Vec2> faceSt, nodeUv;
    std::vector<int> linePoint;
    std::vector<Vec2> lineSt;
  };
  struct GridShape {
    int width = 0, height = 0;   // interior points per row and rows; 0: no grid
    int innerU = 0, innerV = 0;  // Bfr's inner rates
  };

  OpenSubdiv::Bfr::Tessellation faceTessellation(int face, const std::vector<int>& edgeRates,
                                                 FaceScratch& scratch) const;
  // k indexes faces_.
  void layoutOwnedPoints(size_t k, const std::vector<int>& edgeRates);
  // Output point of each boundary coordinate; creates the samples of those the face owns.
  void placeBoundary(size_t k, const std::vector<int>& edgeRates, FaceScratch& scratch);
  GridShape interiorGrid(int face, const OpenSubdiv::Bfr::Tessellation& tess,
                         const FaceScratch& scratch) const;
  // R when the face is a quad of rate R on every edge and grids are asked for: its points are then
  // one (R + 1) x (R + 1) grid, border included (copies of the shared border points, so that the
  // Embree grid holds the whole face and no border triangles are stored); else 0.
  int wholeGridRate(int face, const OpenSubdiv::Bfr::Tessellation& tess,
                    const FaceScratch& scratch) const;
  // The grid of scratch.gridCoord's coordinates (row by row) from firstVertex on, listed in *grid,
  // and its triangles from t on in Embree's order unless gridsOnly_; returns the next triangle.
  size_t emitGrid(int face, size_t firstVertex, int width, int height, size_t t,
                  FaceScratch& scratch, TessellatedMesh& out, TriangleGrid* grid) const;
  // The points and the grid of such a face, its triangles (in grid order) unless gridsOnly_.
  size_t emitWholeGrid(size_t k, int rate, FaceScratch& scratch, TessellatedMesh& out,
                       TriangleGrid* grid);
  // Triangles of the pattern's interior grid that only the grid holds (0 unless gridsOnly_).
  size_t gridOnlyFacets(int face, const OpenSubdiv::Bfr::Tessellation& tess,
                        const FaceScratch& scratch) const;
  // scratch.coords, .st and .point sized for the points of the face's pattern (its boundary's only
  // when boundaryOnly) and the boundary placed (placeBoundary).
  void beginFace(size_t k, const OpenSubdiv::Bfr::Tessellation& tess,
                 const std::vector<int>& edgeRates, bool boundaryOnly, FaceScratch& scratch);
  void emitFace(size_t k, const std::vector<int>& edgeRates, FaceScratch& scratch,
                TessellatedMesh& out, TriangleGrid* grid);
  // Interior points and triangles of one Bfr pattern whose boundary points are placed; returns
  // the next triangle. With `grid`, interior cells as Embree grid cells (see tessellate).
  size_t emitPattern(int face, const OpenSubdiv::Bfr::Tessellation& tess, FaceScratch& scratch,
                     int interiorBase, size_t t, TessellatedMesh& out, TriangleGrid* grid);
  // Split faces (face_split_pattern.cpp): points and triangles a face creates, and its output.
  void countSplitFace(size_t k, const std::vector<int>& edgeRates, const FaceSplit& split,
                      FaceScratch& scratch);
  void emitSplitFace(size_t k, const std::vector<int>& edgeRates, const FaceSplit& split,
                     FaceScratch& scratch, TessellatedMesh& out, std::vector<TriangleGrid>* grids);
  void placeSplitLines(int face, const SplitPattern& pattern, int base, FaceScratch& scratch);
  void placeSubQuadBoundary(const SplitPattern& pattern, int i, int j, FaceScratch& scratch) const;
  // Points the face creates on its mesh vertices and edges.
  size_t ownedBoundaryPoints(int face, const std::vector<int>& edgeRates) const;
  void evaluatePoints(const VertexDisplacement* displacement, TessellatedMesh& out) const;

  const LimitSurface& surface_;
  const LimitSurface::Impl& impl_;
  const LimitSurface::Impl::Topology& base_;
  std::vector<int> faces_;  // faces with a limit surface, in index order
  std::vector<Use> vertexOwner_, edgeOwner_;
  // Per entry of faces_: points the face creates (its share of the boundary and its interior) and
  // triangles, then their prefix sums.
  // numFacets_ counts the triangles stored in the mesh, numGridOnly_ those only grids hold.
  std::vector<size_t> numPoints_, numFacets_, numGridOnly_, pointOffset_, facetOffset_;
  bool gridsOnly_ = false;
  // Grids asked for (tessellate with `grids`): quads of one rate R on every edge are a whole grid
  // of (R + 1)^2 points, their border copies of the shared points (wholeGridRate).
  bool wholeGrids_ = false;
  std::vector<int> vertexPoint_, edgePoint_;  // output point of each vertex, first of each edge
  std::vector<Sample> samples_;               // where each output point lies
};

}  // namespace meso
