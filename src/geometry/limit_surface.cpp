// The limit surface of a subdivision control mesh through OpenSubdiv 3.5 Bfr (Surface per base
// face, evaluated from prepared patch points): P, P_u, P_v and N of shared/DESIGN.md section 5.
#include "meso/geometry/limit_surface.h"

#include "limit_surface_impl.h"
#include "meso/core/check.h"
#include "meso/core/error.h"
#include "meso/core/huge_pages.h"

#include <opensubdiv/bfr/limits.h>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <shared_mutex>
#include <string>

namespace meso {
namespace {

using OpenSubdiv::Bfr::Parameterization;
using Descriptor = OpenSubdiv::Far::TopologyDescriptor;
using RefinerFactory = OpenSubdiv::Far::TopologyRefinerFactory<Descriptor>;
using PointDesc = OpenSubdiv::Bfr::Surface<float>::PointDescriptor;

// The bilinear quad of D-dimensional points p[0 .. 3] at Bfr's (0, 0), (1, 0), (1, 1), (0, 1):
// its value and first derivatives at c.
template <int D>
void bilinearQuad(const float* p, Vec2 c, float* value, float* d0, float* d1) {
  const float u = c.x, v = c.y;
  for (int k = 0; k < D; ++k) {
    const float p0 = p[k], p1 = p[D + k], p2 = p[2 * D + k], p3 = p[3 * D + k];
    value[k] = (1.0f - v) * ((1.0f - u) * p0 + u * p1) + v * ((1.0f - u) * p3 + u * p2);
    d0[k] = (1.0f - v) * (p1 - p0) + v * (p2 - p3);
    d1[k] = (1.0f - u) * (p3 - p0) + u * (p2 - p1);
  }
}

// Whether `surface` is exactly that bilinear quad of its 4 patch points: a regular patch of 4
// points that agrees with bilinearQuad at a few points inside and on the edges (to float rounding
// of the patch's size). Any other patch (a B-spline or Loop patch, an irregular face) is left to
// Bfr.
template <int D>
bool isBilinearQuad(const OpenSubdiv::Bfr::Surface<float>& surface,
                    const std::vector<float>& points, size_t offset) {
  if (!surface.IsValid() || !surface.IsRegular() || surface.GetNumPatchPoints() != 4 ||
      surface.GetParameterization().GetType() != Parameterization::QUAD)
    return false;
  const float* p = &points[offset];
  float size = 0.0f;
  for (int i = 0; i < 4 * D; ++i) size = std::max(size, std::abs(p[i]));
  const float tolerance = 1e-5f * std::max(size, 1e-30f);
  for (const Vec2 c : {Vec2(0.0f), Vec2(1.0f), Vec2(0.3f, 0.8f), Vec2(0.9f, 0.2f), Vec2(0.5f)}) {
    float bv[D], b0[D], b1[D], v[D], d0[D], d1[D];
    surface.Evaluate(&c.x, p, PointDesc(D), v, d0, d1);
    bilinearQuad<D>(p, c, bv, b0, b1);
    for (int k = 0; k < D; ++k)
      if (!(std::abs(bv[k] - v[k]) <= tolerance) || !(std::abs(b0[k] - d0[k]) <= tolerance) ||
          !(std::abs(b1[k] - d1[k]) <= tolerance))
        return false;
  }
  return true;
}

OpenSubdiv::Sdc::SchemeType toSdc(SubdivisionScheme scheme) {
  switch (scheme) {
    case SubdivisionScheme::Loop:
      return OpenSubdiv::Sdc::SCHEME_LOOP;
    case SubdivisionScheme::Bilinear:
      return OpenSubdiv::Sdc::SCHEME_BILINEAR;
    case SubdivisionScheme::CatmullClark:
      break;
  }
  return OpenSubdiv::Sdc::SCHEME_CATMARK;
}

// OpenSubdiv reads out of bounds (or exits) on malformed input, so everything it assumes is checked
// here first.
void validate(const ControlMesh& mesh, SubdivisionScheme scheme) {
  const int numVertices = static_cast<int>(mesh.positions.size());
  if (mesh.numFaces() == 0) throw Error("control mesh has no faces");
  size_t corners = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int n = mesh.faceSizes[f];
    if (n < 3 || n > OpenSubdiv::Bfr::Limits::MaxFaceSize())
      throw Error("control mesh face " + std::to_string(f) + " has " + std::to_string(n) +
                  " vertices (3 to " + std::to_string(OpenSubdiv::Bfr::Limits::MaxFaceSize()) +
                  " supported)");
    if (scheme == SubdivisionScheme::Loop && n != 3)
      throw Error("Loop subdivision needs an all-triangle mesh, but face " + std::to_string(f) +
                  " has " + std::to_string(n) + " vertices");
    corners += static_cast<size_t>(n);
  }
  if (corners != mesh.faceVertices.size())
    throw Error("control mesh face sizes add up to " + std::to_string(corners) + " corners, but " +
                std::to_string(mesh.faceVertices.size()) + " vertex indices are given");
  for (int v : mesh.faceVertices)
    if (v < 0 || v >= numVertices)
      throw Error("control mesh vertex index " + std::to_string(v) + " out of range [0, " +
                  std::to_string(numVertices) + ")");
  if (!mesh.hasUvs()) return;
  if (mesh.uvIndices.size() != mesh.faceVertices.size())
    throw Error("control mesh has " + std::to_string(mesh.uvIndices.size()) + " uv indices for " +
                std::to_string(corners) + " face corners");
  for (int t : mesh.uvIndices)
    if (t < 0 || t >= static_cast<int>(mesh.uvs.size()))
      throw Error("control mesh uv index " + std::to_string(t) + " out of range [0, " +
                  std::to_string(mesh.uvs.size()) + ")");
}

std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> createRefiner(const ControlMesh& mesh,
                                                                SubdivisionScheme scheme) {
  OpenSubdiv::Sdc::Options options;
  options.SetVtxBoundaryInterpolation(OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  // Texture coordinates are interpolated linearly, so (u, v) stays the artist's map on every face.
  options.SetFVarLinearInterpolation(OpenSubdiv::Sdc::Options::FVAR_LINEAR_ALL);

  Descriptor desc;
  desc.numVertices = static_cast<int>(mesh.positions.size());
  desc.numFaces = mesh.numFaces();
  desc.numVertsPerFace = mesh.faceSizes.data();
  desc.vertIndicesPerFace = mesh.faceVertices.data();
  Descriptor::FVarChannel uvChannel;
  if (mesh.hasUvs()) {
    uvChannel.numValues = static_cast<int>(mesh.uvs.size());
    uvChannel.valueIndices = mesh.uvIndices.data();
    desc.numFVarChannels = 1;
    desc.fvarChannels = &uvChannel;
  }
  std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner(
      RefinerFactory::Create(desc, RefinerFactory::Options(toSdc(scheme), options)));
  if (!refiner) throw Error("OpenSubdiv rejected the control mesh topology");
  return refiner;
}

// Offsets of a relation (first[i], then the total) from the sizes of its entries.
template <class Size>
void relationOffsets(int count, std::vector<int>& first, Size&& size) {
  resizePopulated(first, static_cast<size_t>(count) + 1);
  first[0] = 0;
  for (int i = 0; i < count; ++i) first[i + 1] = first[i] + size(i);
}

// The relations that tessellation uses, copied in parallel into arrays made to size, their pages
// mapped on every core (populatePages): on a ground of 400 k faces one thread's copy took 0.1 s,
// mostly the kernel zeroing the pages at their first write.
LimitSurface::Impl::Topology copyTopology(const OpenSubdiv::Far::TopologyLevel& base) {
  LimitSurface::Impl::Topology t;
  t.vertices = base.GetNumVertices();
  const auto each = [](int count, auto&& copy) {
    tbb::parallel_for(tbb::blocked_range<int>(0, count, 4096), [&](const auto& r) {
      for (int i = r.begin(); i != r.end(); ++i) copy(i);
    });
  };
  const int faces = base.GetNumFaces(), edges = base.GetNumEdges();
  relationOffsets(faces, t.faceFirst, [&](int f) { return base.GetFaceVertices(f).size(); });
  resizePopulated(t.faceVertex, static_cast<size_t>(t.faceFirst.back()));
  resizePopulated(t.faceEdge, t.faceVertex.size());
  each(faces, [&](int f) {
    const OpenSubdiv::Far::ConstIndexArray v = base.GetFaceVertices(f), e = base.GetFaceEdges(f);
    std::copy(v.begin(), v.end(), t.faceVertex.begin() + t.faceFirst[f]);
    std::copy(e.begin(), e.end(), t.faceEdge.begin() + t.faceFirst[f]);
  });
  relationOffsets(edges, t.edgeFirst, [&](int e) { return base.GetEdgeFaces(e).size(); });
  resizePopulated(t.edgeFace, static_cast<size_t>(t.edgeFirst.back()));
  each(edges, [&](int e) {
    const OpenSubdiv::Far::ConstIndexArray f = base.GetEdgeFaces(e);
    std::copy(f.begin(), f.end(), t.edgeFace.begin() + t.edgeFirst[e]);
  });
  return t;
}

// A tangent frame for points without derivatives, so callers never normalize a zero vector.
void setTangentFrame(SurfacePoint& sp) {
  const Vec3 a = std::abs(sp.N.x) < 0.9f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
  sp.Pu = glm::normalize(glm::cross(a, sp.N));
  sp.Pv = glm::cross(sp.N, sp.Pu);
}

}  // namespace

namespace {

// Bfr surfaces are initialised from several threads at once: the factory's cache of irregular
// patches (shared by the surfaces of faces with the same topology) then takes a lock.
using ThreadedCache = OpenSubdiv::Bfr::SurfaceFactoryCacheThreaded<
    std::shared_mutex, std::shared_lock<std::shared_mutex>, std::unique_lock<std::shared_mutex>>;
using Factory = OpenSubdiv::Bfr::RefinerSurfaceFactory<ThreadedCache>;

// A Bfr surface kept for the faces of a chunk that evaluate as it does, and what tells them.
struct SharedSurface {
  Parameterization param;
  std::vector<float> stencils;  // weights of P, dP/du, dP/dv at two points
  int index = 0;                // in the chunk's surfaces
};

// The index in `out.surfaces` of a surface that evaluates as `surface` does, stored if it is new.
// A regular patch is evaluated from its patch points by a basis that depends only on its patch
// type and boundary mask (a multilinear N-gon's on N), not on which control points it has: faces
// whose surfaces have the same parameterization and the same basis weights (Bfr's stencils, at two
// points inside any face's first tile) share one, which Evaluate then runs exactly as their own.
// An irregular patch's surface is kept for its face alone.
int storeSurface(const OpenSubdiv::Bfr::Surface<float>& surface, LimitSurface::Impl::Chunk& out,
                 std::vector<SharedSurface>& shared, std::vector<float>& stencils) {
  if (!surface.IsRegular() && !surface.IsLinear()) {
    out.surfaces.push_back(surface);
    return static_cast<int>(out.surfaces.size()) - 1;
  }
  const size_t n = static_cast<size_t>(surface.GetNumControlPoints());
  stencils.resize(6 * n);  // the chunk's scratch: no allocation once it has grown
  const float uv[2][2] = {{0.2f, 0.3f}, {0.35f, 0.1f}};
  for (size_t k = 0; k < 2; ++k) {
    float* w = &stencils[3 * n * k];
    surface.EvaluateStencil(uv[k], w, w + n, w + 2 * n);
  }
  const Parameterization param = surface.GetParameterization();
  for (const SharedSurface& s : shared)
    if (s.param.GetType() == param.GetType() && s.param.GetFaceSize() == param.GetFaceSize() &&
        s.stencils == stencils)
      return s.index;
  out.surfaces.push_back(surface);
  shared.push_back({param, stencils, static_cast<int>(out.surfaces.size()) - 1});
  return shared.back().index;
}

// Whether face f is a quad of the bilinear scheme away from any hole or non-manifold component:
// its limit surface is then the bilinear quad of its corners, and its (u, v) under linear
// face-varying interpolation the bilinear quad of theirs. Bfr finds the same (a regular patch
// whose patch points are the face's control points in the face's order, the same arrays bit for
// bit on every shipped scene's bilinear meshes); prepared without it, such a face skips Bfr's
// set-up and the evaluations that checked its patch.
bool isPlainBilinearQuad(SubdivisionScheme scheme, const OpenSubdiv::Far::TopologyLevel& base,
                         int f) {
  if (scheme != SubdivisionScheme::Bilinear || base.IsFaceHole(f)) return false;
  const OpenSubdiv::Far::ConstIndexArray v = base.GetFaceVertices(f), e = base.GetFaceEdges(f);
  if (v.size() != 4) return false;
  for (int k = 0; k < 4; ++k)
    if (base.IsVertexNonManifold(v[k]) || base.IsEdgeNonManifold(e[k])) return false;
  return true;
}

// The arrays of such a face: its 4 corners' (u, v); its control points are its vertices.
void setBilinearQuad(const ControlMesh& mesh, size_t first, LimitSurface::Impl::Face& face,
                     LimitSurface::Impl::Chunk& out) {
  face.numPatchPoints = 4;
  face.bilinear = true;
  face.gathered = true;
  face.patchOffset = -1;  // its corners: the face's vertices in the base level (Impl::patchPoints)
  if (!mesh.hasUvs()) return;
  face.hasUv = true;
  face.uvBilinear = true;
  face.uvPatchOffset = static_cast<int>(out.uvPatchPoints.size());
  for (int k = 0; k < 4; ++k) {
    const Vec2& uv = mesh.uvs[mesh.uvIndices[first + k]];
    out.uvPatchPoints.push_back(uv.x);
    out.uvPatchPoints.push_back(uv.y);
  }
}

// The faces of one chunk (Impl::Chunk), whose arrays they fill. The chunks are fixed ranges of
// faces, so the arrays are the same whatever the number of threads.
void prepareFaces(const ControlMesh& mesh, SubdivisionScheme scheme, const Factory& factory,
                  const OpenSubdiv::Far::TopologyLevel& base, int begin, int end,
                  const std::vector<size_t>& firstCorner,
                  std::vector<LimitSurface::Impl::Face>& faces, LimitSurface::Impl::Chunk& out) {
  using Face = LimitSurface::Impl::Face;
  // Room for the 4 control points of a quad a face (a plain bilinear quad has none of its own) and
  // its 4 (u, v): a grid's arrays do not grow.
  if (scheme != SubdivisionScheme::Bilinear)
    out.controlIndices.reserve(4 * static_cast<size_t>(end - begin));
  if (mesh.hasUvs()) out.uvPatchPoints.reserve(8 * static_cast<size_t>(end - begin));
  OpenSubdiv::Bfr::Surface<float> surface;
  std::vector<SharedSurface> shared;
  std::vector<float> points, stencils;
  int indices[LimitSurface::Impl::kMaxGathered];
  for (int f = begin; f < end; ++f) {
    Face& face = faces[f];
    const size_t first = firstCorner[f];
    const int n = mesh.faceSizes[f];
    face.param = Parameterization(toSdc(scheme), n);
    if (face.param.HasSubFaces() || n == 3) {
      face.chartOffset = static_cast<int>(out.chartPoints.size());
      Vec3 corners[3];
      if (n == 3)
        for (int k = 0; k < 3; ++k) corners[k] = mesh.positions[mesh.faceVertices[first + k]];
      appendFaceChart(n, corners, out.chartPoints);
    }
    if (isPlainBilinearQuad(scheme, base, f)) {
      setBilinearQuad(mesh, first, face, out);
      continue;
    }
    if (!factory.InitVertexSurface(f, &surface)) continue;  // a hole or non-manifold face
    face.numPatchPoints = surface.GetNumPatchPoints();
    points.resize(3 * static_cast<size_t>(face.numPatchPoints));
    surface.PreparePatchPoints(&mesh.positions[0].x, PointDesc(3), points.data(), PointDesc(3));
    face.bilinear = isBilinearQuad<3>(surface, points, 0);
    if (!face.bilinear) face.surface = storeSurface(surface, out, shared, stencils);
    // A patch whose points are its control points (regular and linear patches) keeps their
    // indices, where they give the same bits.
    face.gathered = face.numPatchPoints <= LimitSurface::Impl::kMaxGathered &&
                    surface.GetNumControlPoints() == face.numPatchPoints;
    if (face.gathered) {
      surface.GetControlPointIndices(indices);
      for (int k = 0; k < face.numPatchPoints && face.gathered; ++k)
        face.gathered =
            indices[k] >= 0 && size_t(indices[k]) < mesh.positions.size() &&
            std::memcmp(&mesh.positions[indices[k]].x, &points[3 * k], 3 * sizeof(float)) == 0;
    }
    if (face.gathered) {
      face.patchOffset = static_cast<int>(out.controlIndices.size());
      out.controlIndices.insert(out.controlIndices.end(), indices, indices + face.numPatchPoints);
    } else {
      face.patchOffset = static_cast<int>(out.patchPoints.size());
      out.patchPoints.insert(out.patchPoints.end(), points.begin(), points.end());
    }
    if (!mesh.hasUvs() || !factory.InitFaceVaryingSurface(f, &surface, 0)) continue;
    face.hasUv = true;
    face.uvPatchOffset = static_cast<int>(out.uvPatchPoints.size());
    out.uvPatchPoints.resize(face.uvPatchOffset + 2 * surface.GetNumPatchPoints());
    surface.PreparePatchPoints(&mesh.uvs[0].x, PointDesc(2), &out.uvPatchPoints[face.uvPatchOffset],
                               PointDesc(2));
    face.uvBilinear = isBilinearQuad<2>(surface, out.uvPatchPoints, face.uvPatchOffset);
    if (!face.uvBilinear) face.uvSurface = storeSurface(surface, out, shared, stencils);
  }
}

}  // namespace

LimitSurface::LimitSurface(const ControlMesh& mesh, SubdivisionScheme scheme)
    : impl_(std::make_unique<Impl>()) {
  validate(mesh, scheme);
  const std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner = createRefiner(mesh, scheme);
  const Factory factory(*refiner);

  const int numFaces = mesh.numFaces();
  resizePopulated(impl_->faces, numFaces);
  std::vector<size_t> firstCorner(static_cast<size_t>(numFaces) + 1, 0);
  for (int f = 0; f < numFaces; ++f)
    firstCorner[f + 1] = firstCorner[f] + static_cast<size_t>(mesh.faceSizes[f]);
  constexpr int kPerChunk = Impl::kFacesPerChunk;
  const int chunks = (numFaces + kPerChunk - 1) / kPerChunk;
  Impl& impl = *impl_;
  impl.controlPoints = mesh.positions;
  impl.chunks.resize(static_cast<size_t>(chunks));
  tbb::parallel_for(0, chunks, [&](int c) {
    Impl::Chunk& chunk = impl.chunks[static_cast<size_t>(c)];
    prepareFaces(mesh, scheme, factory, refiner->GetLevel(0), c * kPerChunk,
                 std::min(numFaces, (c + 1) * kPerChunk), firstCorner, impl.faces, chunk);
    // Kept for the surface's life: without the room the arrays grew into.
    chunk.surfaces.shrink_to_fit();
    chunk.patchPoints.shrink_to_fit();
    chunk.controlIndices.shrink_to_fit();
    chunk.uvPatchPoints.shrink_to_fit();
    chunk.chartPoints.shrink_to_fit();
  });
  impl.topology = copyTopology(refiner->GetLevel(0));
}

LimitSurface::~LimitSurface() = default;
LimitSurface::LimitSurface(LimitSurface&&) noexcept = default;
LimitSurface& LimitSurface::operator=(LimitSurface&&) noexcept = default;

int LimitSurface::numFaces() const { return static_cast<int>(impl_->faces.size()); }

bool LimitSurface::hasLimitSurface(int face) const { return impl_->faces[face].valid(); }

int LimitSurface::faceSize(int face) const { return impl_->faces[face].param.GetFaceSize(); }

Vec2 LimitSurface::cornerSt(int face, int corner) const { return impl_->cornerSt(face, corner); }

bool LimitSurface::faceBox(int face, Vec3& lo, Vec3& hi) const {
  const Impl::Face& f = impl_->faces[face];
  if (!f.valid()) return false;
  lo = Vec3(std::numeric_limits<float>::infinity());
  hi = -lo;
  float gathered[3 * Impl::kMaxGathered];
  const float* p = impl_->patchPoints(face, gathered);
  for (int i = 0; i < f.numPatchPoints; ++i, p += 3) {
    lo = glm::min(lo, Vec3(p[0], p[1], p[2]));
    hi = glm::max(hi, Vec3(p[0], p[1], p[2]));
  }
  return true;
}

bool LimitSurface::derivativeKey(int face, DerivativeKey& key) const {
  const Impl::Face& f = impl_->faces[face];
  // evaluate() then reads: the chart (the identity for chartOffset < 0), bilinearQuad's
  // differences of the patch points and of the (u, v) points, and the fallback normal of
  // limitNormal (its insets also stay in Bfr's coordinates).
  if (!f.valid() || !f.bilinear || f.chartOffset >= 0 || (f.hasUv && !f.uvBilinear)) return false;
  float gathered[3 * Impl::kMaxGathered];
  const float* p = impl_->patchPoints(face, gathered);
  float* out = key.values.data();
  const auto differences = [&out](const float* q, int d) {
    for (int k = 0; k < d; ++k) {
      out[k] = q[d + k] - q[k];                  // P1 - P0
      out[d + k] = q[2 * d + k] - q[3 * d + k];  // P2 - P3
      out[2 * d + k] = q[3 * d + k] - q[k];      // P3 - P0
      out[3 * d + k] = q[2 * d + k] - q[d + k];  // P2 - P1
    }
    out += 4 * d;
  };
  key.values.fill(0.0f);
  differences(p, 3);
  if (f.hasUv)
    differences(impl_->uvPatchPoints(face), 2);
  else
    out += 8;
  Vec3 centroid, normal;
  impl_->polygonFrame(face, centroid, normal);
  *out++ = normal.x;
  *out++ = normal.y;
  *out++ = normal.z;
  *out = f.hasUv ? 1.0f : 0.0f;
  return true;
}

int DerivativeSweep::sameAs(int face) {
  const bool keyed = surface_.derivativeKey(face, key_);
  if (keyed && lastFace_ >= 0 && key_ == last_) return lastFace_;
  last_ = key_;
  lastFace_ = keyed ? face : -1;
  return -1;
}

void LimitSurface::Impl::polygonFrame(int face, Vec3& centroid, Vec3& normal) const {
  const Topology::Indices v = topology.faceVertices(face);
  const int size = v.size();
  Vec3 sum(0.0f), newell(0.0f);
  for (int i = 0; i < size; ++i) {
    const Vec3& a = controlPoints[v[i]];
    const Vec3& b = controlPoints[v[(i + 1) % size]];
    sum += a;
    newell += Vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  centroid = sum / static_cast<float>(size);
  const float len = glm::length(newell);
  normal = (len > 0.0f && std::isfinite(len)) ? newell / len : Vec3(0.0f, 0.0f, 1.0f);
}

size_t LimitSurface::Impl::Topology::memoryBytes() const {
  return sizeof(int) * (faceFirst.capacity() + faceVertex.capacity() + faceEdge.capacity() +
                        edgeFirst.capacity() + edgeFace.capacity());
}

size_t LimitSurface::Impl::Chunk::memoryBytes() const {
  return sizeof(Chunk) + surfaces.capacity() * sizeof(OpenSubdiv::Bfr::Surface<float>) +
         (patchPoints.capacity() + uvPatchPoints.capacity()) * sizeof(float) +
         controlIndices.capacity() * sizeof(int) + chartPoints.capacity() * sizeof(Vec2);
}

size_t LimitSurface::memoryBytes() const {
  const Impl& i = *impl_;
  double bytes = sizeof(Impl) + double(i.faces.capacity()) * sizeof(Impl::Face) +
                 double(i.controlPoints.capacity()) * sizeof(Vec3);
  for (const Impl::Chunk& chunk : i.chunks) bytes += double(chunk.memoryBytes());
  bytes += double(i.topology.memoryBytes());
  return static_cast<size_t>(bytes);
}

namespace {

// Derivatives with respect to Bfr's coordinates at c.
void evaluateDerivatives(const LimitSurface::Impl& impl, int face, Vec2 c, Vec3& P, Vec3& dPdc0,
                         Vec3& dPdc1) {
  const LimitSurface::Impl::Face& f = impl.faces[face];
  float gathered[3 * LimitSurface::Impl::kMaxGathered];
  const float* points = impl.patchPoints(face, gathered);
  if (f.bilinear)
    bilinearQuad<3>(points, c, &P.x, &dPdc0.x, &dPdc1.x);
  else
    impl.chunkOf(face).surfaces[f.surface].Evaluate(&c.x, points, PointDesc(3), &P.x, &dPdc0.x,
                                                    &dPdc1.x);
}

bool usableCross(const Vec3& a, const Vec3& b, Vec3& n) {
  n = glm::cross(a, b);
  const float len2 = glm::dot(n, n);
  // Relative test: nearly parallel derivatives give a cross product that is mostly rounding error
  // (|n| > 1e-6 |a| |b|, squared: one square root per call, in the hot path of shading and dicing).
  const double ab2 = static_cast<double>(glm::dot(a, a)) * glm::dot(b, b);
  if (!(len2 > 1e-12 * ab2) || !(len2 > 0.0f) || !std::isfinite(len2)) return false;
  n /= std::sqrt(len2);
  return true;
}

// N from Bfr's derivatives (their orientation is the mesh's for every face). Where they are
// degenerate (a collapsed face, some extraordinary corners) the normal slightly inside the face is
// the limit of the normals around the point; the control polygon's normal is the last resort.
// The inset moves st towards the chart's centre (or, from the centre, towards corner 0) in meso's
// chart, where the face is one connected domain.
Vec3 limitNormal(const LimitSurface::Impl& impl, int face, Vec2 st, const Vec3& dPdc0,
                 const Vec3& dPdc1) {
  Vec3 n;
  if (usableCross(dPdc0, dPdc1, n)) return n;
  const LimitSurface::Impl::Face& f = impl.faces[face];
  Vec2 centre(0.5f), corner(0.0f);
  if (f.chartOffset >= 0) {
    centre = impl.chartPoints(face)[f.param.GetFaceSize()];
    corner = impl.chartPoints(face)[0];
  }
  const Vec2 target = glm::length(st - centre) > 1e-3f ? centre : corner;
  for (float inset : {1e-4f, 1e-3f, 1e-2f, 1e-1f}) {
    glm::mat2 unused;
    const Vec2 c = impl.chartToBfr(face, st + inset * (target - st), unused);
    Vec3 P, d0, d1;
    evaluateDerivatives(impl, face, c, P, d0, d1);
    if (usableCross(d0, d1, n)) return n;
  }
  Vec3 centroid, normal;
  impl.polygonFrame(face, centroid, normal);
  return normal;
}

// Pu, Pv with respect to texture coordinates: [Pu Pv] = [dP/dc] (d uv / dc)^-1.
bool textureDerivatives(const LimitSurface::Impl& impl, int face, Vec2 c, const Vec3& dPdc0,
                        const Vec3& dPdc1, SurfacePoint& sp) {
  const LimitSurface::Impl::Face& f = impl.faces[face];
  Vec2 dUv0, dUv1;
  if (f.uvBilinear)
    bilinearQuad<2>(impl.uvPatchPoints(face), c, &sp.uv.x, &dUv0.x, &dUv1.x);
  else
    impl.chunkOf(face).surfaces[f.uvSurface].Evaluate(&c.x, impl.uvPatchPoints(face), PointDesc(2),
                                                      &sp.uv.x, &dUv0.x, &dUv1.x);
  const float det = cross2(dUv0, dUv1);
  // A folded or collapsed uv map has no inverse; the caller then keeps patch derivatives.
  if (!(std::abs(det) > 1e-8f * glm::length(dUv0) * glm::length(dUv1)) || !(det != 0.0f))
    return false;
  const Vec3 pu = (dPdc0 * dUv1.y - dPdc1 * dUv0.y) / det;
  const Vec3 pv = (dPdc1 * dUv0.x - dPdc0 * dUv1.x) / det;
  if (!isFinite(pu) || !isFinite(pv)) return false;
  sp.Pu = pu;
  sp.Pv = pv;
  return true;
}

}  // namespace

SurfacePoint LimitSurface::evaluate(int face, Vec2 st) const {
  MESO_DCHECK(face >= 0 && face < numFaces(), "a base face of this surface");
  const Impl::Face& f = impl_->faces[face];
  SurfacePoint sp;
  if (!f.valid()) {
    impl_->polygonFrame(face, sp.P, sp.N);
    sp.uv = st;
    setTangentFrame(sp);
    return sp;
  }
  glm::mat2 dcdst;
  const Vec2 c = impl_->chartToBfr(face, st, dcdst);
  Vec3 dPdc0, dPdc1;
  evaluateDerivatives(*impl_, face, c, sp.P, dPdc0, dPdc1);
  sp.N = limitNormal(*impl_, face, st, dPdc0, dPdc1);
  if (f.hasUv && textureDerivatives(*impl_, face, c, dPdc0, dPdc1, sp)) return sp;
  if (!f.hasUv) sp.uv = impl_->bfrToChart(face, c);  // st, clamped into the face
  // Chain rule through the chart: column k of dcdst is d(Bfr uv)/d(st_k).
  sp.Pu = dPdc0 * dcdst[0][0] + dPdc1 * dcdst[0][1];
  sp.Pv = dPdc0 * dcdst[1][0] + dPdc1 * dcdst[1][1];
  return sp;
}

}  // namespace meso
