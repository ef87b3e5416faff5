// Kautz et al. 2001, section 7: an existing bump map converted to a texture of indices into
// L(r1, r2), "so that the original normals will be looked up", with noise added when zooming in.
#pragma once

#include "meso/relief/height_source.h"
#include "meso/synthesis/normal_lookup_table.h"
#include "meso/synthesis/synthesis_sampler.h"

#include <vector>

namespace meso {

// indices(i, j) = (r1, r2) = L^-1(n) for the relief normal n = normalize(-s grad h(p), 1) at the
// texel centre p = ((i + 0.5) / res, (j + 0.5) / res) of the tile [0, 1)^2 (s = slopeScale, as in
// NdfEstimateOptions). The paper writes r = G(M(n_x)), G(C(n_y | n_x)); here the index is stored
// in L's own uniform domain, r = (M(n_x), C(n_y | n_x)) refined to the exact inverse of the
// bilinear table (NormalLookupTable::invert), and the turbulence domain is reached through G^-1
// when noise is added. Normals L cannot reach (outside the NDF's support box) clamp per axis.
// Immutable after construction; the lookups are allocation-free and thread-safe.
class IndexTexture {
 public:
  IndexTexture(const HeightSource& source, const NormalLookupTable& table, int resolution,
               float slopeScale = 1.0f);

  int resolution() const { return res_; }
  // The stored index of texel (i, j) (wrapped into the tile).
  Vec2 index(int i, int j) const;
  // The index at tile point p: bilinear between texel centres, periodic. Filtering indices rather
  // than normals is what the paper recommends (no denormalized normals).
  Vec2 index(Vec2 p) const;
  // The relief normal at texel (i, j) that the index encodes (what the round trip must give back).
  Vec3 originalNormal(int i, int j) const { return normals_[offset(i, j)]; }

  // The normal with detail added (amplitude >= 0):
  //   t = (G^-1(index(p); c) + amplitude * turbulence(p, c)) / sqrt(1 + amplitude^2),
  //   n = L(G(t; c)),
  // channel by channel, with the sampler's turbulence, G and L (the sampler must use the table this
  // texture was built for). amplitude 0 gives L(index(p)), the relief's own normal; the division
  // keeps the spread of t, so a large amplitude fades to plain synthesis (NDF-distributed normals).
  // p is in tile coordinates for the index and in surface units for the turbulence.
  Vec3 normal(const SynthesisSampler& sampler, Vec2 p, float amplitude, float c) const;

 private:
  size_t offset(int i, int j) const;
  int res_;
  std::vector<Vec2> indices_;
  std::vector<Vec3> normals_;
};

}  // namespace meso
