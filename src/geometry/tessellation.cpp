// Watertight uniform tessellation of a limit surface with OpenSubdiv 3.5 Bfr::Tessellation, sharing
// the points of mesh vertices and edges between faces as in OpenSubdiv's tutorial_2_2.
#include "meso/geometry/tessellation.h"

#include "limit_surface_impl.h"
#include "meso/core/error.h"

#include <opensubdiv/bfr/tessellation.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <map>
#include <string>
#include <utility>

namespace meso {
namespace {

using OpenSubdiv::Bfr::Tessellation;
using OpenSubdiv::Far::ConstIndexArray;

// Builds the connectivity face by face and records where each output point lies (a face and its
// st there); the points are evaluated afterwards, in parallel, by evaluatePoints().
class Tessellator {
 public:
  Tessellator(const LimitSurface& surface, TessellatedMesh& out)
      : impl_(surface.impl()),
        base_(impl_.refiner->GetLevel(0)),
        out_(out),
        vertexPoint_(base_.GetNumVertices(), -1),
        edgePoint_(base_.GetNumEdges(), -1) {}

  void tessellateFace(int face, int rate) {
    const Pattern& pattern = patternFor(face, rate);
    shareBoundary(face, pattern);
    // Interior points belong to this face alone.
    const int interiorBase = static_cast<int>(samples_.size());
    for (int j = pattern.numBoundary; j < pattern.numCoords(); ++j)
      samples_.push_back({face, st(face, pattern, j)});
    addFacets(face, pattern, interiorBase);
  }

  void evaluatePoints(const LimitSurface& surface) {
    out_.positions.resize(samples_.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, samples_.size(), 256),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i)
                          out_.positions[i] = surface.evaluate(samples_[i].face, samples_[i].st).P;
                      });
  }

 private:
  struct Sample {
    int face;
    Vec2 st;
  };

  // Bfr's tessellation of one face size at the uniform rate (the scheme is the surface's).
  struct Pattern {
    int numBoundary = 0;
    std::vector<int> edgeCoords;  // points inside each edge
    std::vector<float> coords;    // Bfr (u, v) pairs: boundary first, then interior
    std::vector<int> facets;      // 3 coordinate indices per triangle
    int numCoords() const { return static_cast<int>(coords.size() / 2); }
  };

  const Pattern& patternFor(int face, int rate) {
    const auto& param = impl_.faces[face].param;
    Pattern& p = patterns_[param.GetFaceSize()];
    if (!p.coords.empty()) return p;
    Tessellation::Options options;
    options.SetFacetSize(3);
    const Tessellation tess(param, rate, options);
    p.numBoundary = tess.GetNumBoundaryCoords();
    for (int e = 0; e < param.GetFaceSize(); ++e) p.edgeCoords.push_back(tess.GetNumEdgeCoords(e));
    p.coords.resize(2 * static_cast<size_t>(tess.GetNumCoords()));
    tess.GetCoords(p.coords.data());
    p.facets.resize(3 * static_cast<size_t>(tess.GetNumFacets()));
    tess.GetFacets(p.facets.data());
    return p;
  }

  Vec2 st(int face, const Pattern& pattern, int coord) const {
    return impl_.bfrToChart(face, Vec2(pattern.coords[2 * coord], pattern.coords[2 * coord + 1]));
  }

  // Bfr lists boundary coordinates as vertex 0, the points of edge 0, vertex 1, ... The first face
  // to reach a mesh vertex or edge creates its points; later faces reuse them, so neighbours share
  // identical vertices and the mesh has no cracks.
  void shareBoundary(int face, const Pattern& pattern) {
    const ConstIndexArray verts = base_.GetFaceVertices(face);
    const ConstIndexArray edges = base_.GetFaceEdges(face);
    boundary_.assign(pattern.numBoundary, -1);
    int b = 0;
    for (int i = 0; i < verts.size(); ++i) {
      int& vertex = vertexPoint_[verts[i]];
      if (vertex < 0) {
        vertex = static_cast<int>(samples_.size());
        samples_.push_back({face, st(face, pattern, b)});
      }
      boundary_[b++] = vertex;
      const int n = pattern.edgeCoords[i];
      if (n <= 0) continue;
      // Edge points are stored from the lower to the higher mesh vertex index, whichever way the
      // face runs along the edge.
      const bool forward = verts[i] < verts[(i + 1) % verts.size()];
      int& first = edgePoint_[edges[i]];
      if (first < 0) {
        first = static_cast<int>(samples_.size());
        samples_.resize(samples_.size() + n);
        for (int j = 0; j < n; ++j)
          samples_[first + (forward ? j : n - 1 - j)] = {face, st(face, pattern, b + j)};
      }
      for (int j = 0; j < n; ++j) boundary_[b++] = first + (forward ? j : n - 1 - j);
    }
  }

  // Facets keep the corners' st in their own face; corners are ordered counter-clockwise in st,
  // which is the orientation of the limit normal (dP/ds x dP/dt).
  void addFacets(int face, const Pattern& pattern, int interiorBase) {
    const int numBoundary = pattern.numBoundary;
    for (size_t k = 0; k < pattern.facets.size(); k += 3) {
      int c[3] = {pattern.facets[k], pattern.facets[k + 1], pattern.facets[k + 2]};
      Vec2 s[3] = {st(face, pattern, c[0]), st(face, pattern, c[1]), st(face, pattern, c[2])};
      const Vec2 e1 = s[1] - s[0], e2 = s[2] - s[0];
      if (e1.x * e2.y - e1.y * e2.x < 0.0f) {
        std::swap(c[1], c[2]);
        std::swap(s[1], s[2]);
      }
      for (int j = 0; j < 3; ++j) {
        const int point = c[j] < numBoundary ? boundary_[c[j]] : interiorBase + c[j] - numBoundary;
        out_.indices.push_back(static_cast<uint32_t>(point));
        out_.cornerSt.push_back(s[j]);
      }
      out_.triangleFace.push_back(face);
    }
  }

  const LimitSurface::Impl& impl_;
  const OpenSubdiv::Far::TopologyLevel& base_;
  TessellatedMesh& out_;
  std::vector<Sample> samples_;      // one per output point
  std::vector<int> vertexPoint_;     // output point of each mesh vertex, -1 until created
  std::vector<int> edgePoint_;       // first output point of each mesh edge, -1 until created
  std::map<int, Pattern> patterns_;  // by face size
  std::vector<int> boundary_;        // output point of each boundary coordinate of the face
};

}  // namespace

TessellatedMesh tessellateUniform(const LimitSurface& surface, int rate) {
  if (rate < 1)
    throw Error("tessellation rate must be at least 1 (got " + std::to_string(rate) + ")");
  TessellatedMesh out;
  Tessellator tessellator(surface, out);
  for (int f = 0; f < surface.numFaces(); ++f)
    if (surface.hasLimitSurface(f)) tessellator.tessellateFace(f, rate);
  tessellator.evaluatePoints(surface);
  return out;
}

}  // namespace meso
