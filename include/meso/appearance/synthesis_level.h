// Kautz, Heidrich & Seidel 2001 as the finest level of a material (DESIGN.md sections 1, 2, 6):
// normals synthesized from turbulence through G and L(r1, r2), shaded with the NDF, with octaves
// fading in as one zooms. Kautz et al. shade every synthesized microfacet with the full NDF, which
// makes a near view rougher (and dimmer in the highlight) than the far one. meso keeps intensity
// consistent across distance instead: the NDF's slope spread is shared between the synthesized
// structure and the microfacets' own lobe. L draws from the NDF with slopes scaled by
// sqrt(kStructureShare); the lobe is the NDF with slopes scaled by sqrt(1 - kStructureShare w0^2),
// w0 the first octave's fade-in weight. Far away (w0 = 0) that is the NDF itself; once detail is
// in, structure and lobe convolve back to the NDF (exactly for Gaussian slope distributions).
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/core/memory_budget.h"
#include "meso/synthesis/index_texture.h"
#include "meso/synthesis/ndf.h"
#include "meso/synthesis/synthesis_sampler.h"
#include "meso/scene/scene.h"

#include <memory>

namespace meso {

class HeightSource;

inline constexpr float kStructureShare = 0.6f;

// An NDF with its slopes scaled by k (k < 1 narrower): D_k(m) = D(m') cos^4(m') / (k^2 cos^4(m)),
// m' the normal of slope s(m) / k. The slope density scales as p_k(s) = p(s / k) / k^2, so D_k
// stays normalized (integral D_k cos dw = 1). Does not own the NDF.
class ScaledSlopeNdf : public Ndf {
 public:
  ScaledSlopeNdf(const Ndf& ndf, float k) : ndf_(&ndf), k_(k) {}
  float D(const Vec3& m) const override;
  Vec2 support() const override;
  std::string name() const override;
  uint64_t fingerprint() const override;

 private:
  const Ndf* ndf_;
  float k_;
};

// The NDF a declaration names. `finest` is the material's finest relief level (type "relief"
// estimates the NDF from its slopes, Kautz et al. section 7, and sets *principalAngle, radians, to
// the direction of largest slope variance; may be null otherwise). Throws meso::Error naming the
// declaration for unreadable NDF images and images larger than memoryLimitBytes allows.
std::unique_ptr<Ndf> makeNdf(const NdfDecl& decl, const HeightSource* finest, float finestScale,
                             float finestAmplitude, float* principalAngle = nullptr,
                             uint64_t memoryLimitBytes = defaultMemoryLimitBytes());

struct SynthesisLevel {
  std::unique_ptr<Ndf> ndf;        // the material's NDF: far shading, the finest BRDF's lobe
  std::unique_ptr<Ndf> structure;  // ndf scaled by sqrt(kStructureShare): what L draws from
  std::unique_ptr<SynthesisSampler> sampler;
  float peak = 1.0f;  // ndf->D(z): the specular unit (ks at the mirror direction)
  float cosAngle = 1.0f, sinAngle = 0.0f;  // the NDF's x axis, from P_u towards P_v
  bool lambert = true;
  double seconds = 0.0;  // build time
  // type "relief": the finest relief level as indices into L (Kautz et al. section 7), so that the
  // synthesized detail continues that level's own normals and noise is added as one zooms in.
  std::unique_ptr<IndexTexture> index;
  float indexScale = 1.0f;  // the finest level's tiling S: tile coordinates = S uv

  // The lobe (H.n) -> D(h) / peak of an isotropic version of the NDF (the average over the x and y
  // axes), for the finest level's BRDF table (Figure 2's first branch over the NDF model).
  SpecularLobe lobe() const;
};

// baseFrequency: turbulence lattice cells per unit of u at octave 0 (decl.scale, or the default
// the caller derives from the relief). principalAngle (radians) turns the NDF's x axis further.
// `finest` (type "relief" only; may be null) is the level the index texture encodes, with its
// amplitude and tiling scale.
std::unique_ptr<SynthesisLevel> buildSynthesisLevel(
    const NdfDecl& decl, std::unique_ptr<Ndf> ndf, float baseFrequency, float principalAngle = 0.0f,
    const HeightSource* finest = nullptr, float finestScale = 1.0f, float finestAmplitude = 0.0f);

}  // namespace meso
