// Kautz et al. 2001, sections 4 and 5.1: the synthesized bump map, n_m = L(G(t1), G(t2)) with
// (t1, t2) the turbulence at the sample and its level of detail.
#pragma once

#include "meso/synthesis/ndf.h"
#include "meso/synthesis/normal_lookup_table.h"
#include "meso/synthesis/turbulence.h"
#include "meso/synthesis/turbulence_cdf.h"

namespace meso {

struct SynthesisOptions {
  TurbulenceOptions turbulence;
  TurbulenceCdfOptions cdf;
  NormalLookupOptions table;
};

// Turbulence (2 channels) -> G -> L: a microfacet normal distributed by the NDF wherever the
// turbulence has at least one octave in (pixelsPerUnit large enough), with spatial coherence
// (neighbouring samples get neighbouring normals) and more detail the closer one looks.
// Does not own the NDF: it must outlive the sampler. Building costs the G rows (~0.35 s with the
// defaults) and the table (~30 ms); normal() is allocation-free and thread-safe.
class SynthesisSampler {
 public:
  SynthesisSampler(const Ndf& ndf, const SynthesisOptions& options);
  explicit SynthesisSampler(const Ndf& ndf) : SynthesisSampler(ndf, SynthesisOptions{}) {}

  // (r1, r2) = (G(t1; c), G(t2; c)) at uv (units of the surface parameter) and octave count c.
  Vec2 indices(Vec2 uv, float c) const { return cdf_.G(turbulence_.evaluate(uv, c), c); }
  // The unit microfacet normal L(r1, r2) in the NDF's frame (z = the macro normal, x = the NDF's
  // principal axis) at uv, where one unit of uv spans pixelsPerUnit pixels (1 / footprint).
  Vec3 normal(Vec2 uv, float pixelsPerUnit) const {
    return normalAtCount(uv, turbulence_.octaveCount(pixelsPerUnit));
  }
  // The same for an explicit octave count c (Turbulence::octaveCount).
  Vec3 normalAtCount(Vec2 uv, float c) const { return table_.lookup(indices(uv, c)); }

  const Ndf& ndf() const { return *ndf_; }
  const Turbulence& turbulence() const { return turbulence_; }
  const TurbulenceCdf& cdf() const { return cdf_; }
  const NormalLookupTable& table() const { return table_; }

 private:
  const Ndf* ndf_;
  Turbulence turbulence_;
  TurbulenceCdf cdf_;
  NormalLookupTable table_;
};

}  // namespace meso
