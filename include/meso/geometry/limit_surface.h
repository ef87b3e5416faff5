// The limit surface of a control mesh (OpenSubdiv Far + Bfr), evaluated per base face.
#pragma once

#include "meso/core/math.h"
#include "meso/geometry/control_mesh.h"

#include <array>
#include <cstring>
#include <memory>

namespace meso {

// A point of the limit surface with its first derivatives. Pu, Pv are the derivatives with respect
// to the texture coordinates (u, v) when the mesh has them, otherwise with respect to the face's
// own patch coordinates (s, t). N is the unit limit normal, facing the mesh's outward side (so N =
// -normalize(Pu x Pv) for a mirrored uv map), never a facet normal (Chan 2002).
struct SurfacePoint {
  Vec3 P{0.0f};
  Vec3 Pu{0.0f};
  Vec3 Pv{0.0f};
  Vec3 N{0.0f, 0.0f, 1.0f};
  Vec2 uv{0.0f};  // texture coordinates (face-varying if present, else the patch coordinates)
};

// What a face's derivatives (SurfacePoint::Pu, Pv, N) depend on, where LimitSurface::derivativeKey
// finds it: two faces with equal keys (bit for bit) have the same Pu, Pv and N at every st.
struct DerivativeKey {
  // The patch's edge differences P1 - P0, P2 - P3, P3 - P0, P2 - P1 (bilinearQuad's derivatives
  // are made of these alone), the same of the (u, v) patch when the face has (u, v), the face's
  // fallback normal, and whether it has (u, v).
  std::array<float, 24> values{};
  bool operator==(const DerivativeKey& o) const {
    return std::memcmp(values.data(), o.values.data(), sizeof(values)) == 0;
  }
};

class LimitSurface {
 public:
  // Throws meso::Error if OpenSubdiv rejects the topology.
  LimitSurface(const ControlMesh& mesh, SubdivisionScheme scheme);
  ~LimitSurface();
  LimitSurface(LimitSurface&&) noexcept;
  LimitSurface& operator=(LimitSurface&&) noexcept;

  int numFaces() const;
  // False for faces that have no limit surface (holes, some non-manifold configurations).
  bool hasLimitSurface(int face) const;
  // Number of patch-coordinate parameterization edges of the face (4 for quads, 3 for triangles
  // under Loop, N for an N-gon).
  int faceSize(int face) const;
  // Evaluates the limit surface of base face `face` at patch coordinates st. Allocation-free and
  // thread-safe: everything it needs is prepared in the constructor.
  SurfacePoint evaluate(int face, Vec2 st) const;
  // Patch coordinates of corner `corner` of the face (the st domain's corners, in face order).
  Vec2 cornerSt(int face, int corner) const;
  // The box of the face's patch points, which contains its limit patch (convex hull property).
  // False for a face without a limit surface.
  bool faceBox(int face, Vec3& lo, Vec3& hi) const;
  // For a quad whose limit patch and (u, v) patch are the bilinear quads of their points, in Bfr's
  // own patch coordinates (a plain quad of the bilinear scheme, as a flat ground's faces are):
  // fills `key` and returns true. Faces with equal keys then evaluate to the same Pu, Pv and N at
  // every st (only P and uv differ), so a sweep over many faces of one shape evaluates one of
  // them. False for every other face.
  bool derivativeKey(int face, DerivativeKey& key) const;
  // The bytes it holds: its own arrays (their capacity), the Bfr surfaces of faces that are not
  // bilinear quads, and OpenSubdiv's base-level topology estimated from its counts of faces,
  // corners, edges and vertices (within 10% of the heap it takes on grids and tori, tested).
  size_t memoryBytes() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// A sweep over a surface's faces that evaluates a face only where its derivative key differs from
// that of the last face it evaluated: sameAs(face) gives that earlier face when their keys are
// equal (then the face's Pu, Pv and N at any st are that face's, bit for bit), otherwise -1, and
// the face becomes the one the next is compared with. On a ground of equal quads nearly every
// face is the same as the one before.
class DerivativeSweep {
 public:
  explicit DerivativeSweep(const LimitSurface& surface) : surface_(surface) {}
  int sameAs(int face);

 private:
  const LimitSurface& surface_;
  DerivativeKey key_, last_;
  int lastFace_ = -1;
};

}  // namespace meso
