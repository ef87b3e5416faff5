// Kautz, Heidrich & Seidel 2001, sections 4 and 5.1, with the consistency rule of
// synthesis_level.h.
#include "meso/appearance/synthesis_level.h"

#include "meso/core/error.h"
#include "meso/core/hash.h"
#include "meso/core/image_io.h"
#include "meso/core/timer.h"
#include "meso/relief/height_source.h"
#include "meso/synthesis/beckmann_ndf.h"
#include "meso/synthesis/blinn_phong_ndf.h"
#include "meso/synthesis/ndf_estimate.h"
#include "meso/synthesis/tabulated_ndf.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace meso {
namespace {

// The unit normal of slope s: normalize(-s.x, -s.y, 1).
Vec3 normalOfSlope(Vec2 s) { return glm::normalize(Vec3(-s.x, -s.y, 1.0f)); }

std::unique_ptr<Ndf> tabulatedFromImage(const NdfDecl& decl, uint64_t memoryLimitBytes) {
  try {
    const Image img = readImage(decl.image, memoryLimitBytes);
    if (img.width < 2 || img.height < 2)
      throw Error(decl.image.string() + ": an NDF image needs at least 2 x 2 pixels");
    // One channel, or the luminance of RGB(A); image row 0 (the top) is m.y = +1.
    std::vector<float> values(static_cast<size_t>(img.width) * img.height);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        float v = img.at(x, y, 0);
        if (img.numChannels() >= 3)
          v = 0.2126f * img.at(x, y, 0) + 0.7152f * img.at(x, y, 1) + 0.0722f * img.at(x, y, 2);
        values[static_cast<size_t>(img.height - 1 - y) * img.width + x] = v;
      }
    return std::make_unique<TabulatedNdf>(img.width, img.height, std::move(values));
  } catch (const Error& e) {
    throw Error(decl.loc, "materials.ndf.image", e.what());
  }
}

}  // namespace

float ScaledSlopeNdf::D(const Vec3& m) const {
  if (!(m.z > 0.0f)) return 0.0f;
  const Vec2 s(-m.x / m.z, -m.y / m.z);
  const Vec3 mp = normalOfSlope(s / k_);
  const float c = m.z * m.z, cp = mp.z * mp.z;
  const float d = ndf_->D(mp) * (cp * cp) / (k_ * k_ * c * c);
  return std::isfinite(d) ? d : 0.0f;
}

Vec2 ScaledSlopeNdf::support() const {
  const Vec2 s = ndf_->support();
  const auto scale = [this](float x) {
    if (x >= 1.0f) return 1.0f;
    const float slope = k_ * x / std::sqrt(std::max(1e-12f, 1.0f - x * x));
    return std::min(1.0f, slope / std::sqrt(1.0f + slope * slope));
  };
  return {scale(s.x), scale(s.y)};
}

std::string ScaledSlopeNdf::name() const {
  return ndf_->name() + fmt::format(" slopes x {:.4g}", k_);
}

uint64_t ScaledSlopeNdf::fingerprint() const {
  return Hasher().string("ScaledSlopeNdf").value(ndf_->fingerprint()).value(k_).digest();
}

std::unique_ptr<Ndf> makeNdf(const NdfDecl& decl, const HeightSource* finest, float finestScale,
                             float finestAmplitude, float* principalAngle,
                             uint64_t memoryLimitBytes) {
  if (principalAngle) *principalAngle = 0.0f;
  switch (decl.type) {
    case NdfType::Beckmann:
      return std::make_unique<BeckmannNdf>(decl.alpha.x, decl.alpha.y);
    case NdfType::BlinnPhong:
      return std::make_unique<BlinnPhongNdf>(decl.exponent);
    case NdfType::Tabulated:
      return tabulatedFromImage(decl, memoryLimitBytes);
    case NdfType::Relief:
      break;
  }
  if (!finest)
    throw Error(decl.loc, "materials.ndf.type",
                "\"relief\" needs a relief level to estimate the NDF from");
  // Kautz et al. section 7: the NDF of the finest level's own slopes (Beckmann in its principal
  // frame).
  NdfEstimateOptions options;
  options.slopeScale = finestAmplitude * finestScale;
  NdfEstimate e = estimateNdf(*finest, options);
  if (principalAngle) *principalAngle = e.principalAngle;
  return std::move(e.ndf);
}

SpecularLobe SynthesisLevel::lobe() const {
  const Ndf* d = ndf.get();
  const float p = peak;
  return {[d, p](float c) {
            const float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
            if (!(c > 0.0f)) return 0.0f;
            return 0.5f * (d->D(Vec3(s, 0.0f, c)) + d->D(Vec3(0.0f, s, c))) / p;
          },
          Hasher().string("ndf lobe").value(ndf->fingerprint()).digest()};
}

std::unique_ptr<SynthesisLevel> buildSynthesisLevel(const NdfDecl& decl, std::unique_ptr<Ndf> ndf,
                                                    float baseFrequency, float principalAngle,
                                                    const HeightSource* finest, float finestScale,
                                                    float finestAmplitude) {
  Timer timer;
  auto level = std::make_unique<SynthesisLevel>();
  level->ndf = std::move(ndf);
  level->structure = std::make_unique<ScaledSlopeNdf>(*level->ndf, std::sqrt(kStructureShare));
  SynthesisOptions options;
  options.turbulence.baseFrequency = baseFrequency;
  options.turbulence.lacunarity = decl.lacunarity;
  options.turbulence.gain = decl.gain;
  options.turbulence.maxOctaves = decl.octaves;
  options.turbulence.seed = decl.seed;
  level->sampler = std::make_unique<SynthesisSampler>(*level->structure, options);
  level->peak = std::max(level->ndf->D(Vec3(0.0f, 0.0f, 1.0f)), 1e-20f);
  level->cosAngle = std::cos(radians(decl.angle) + principalAngle);
  level->sinAngle = std::sin(radians(decl.angle) + principalAngle);
  level->lambert = decl.lambert;
  if (decl.type == NdfType::Relief && finest) {
    level->index = std::make_unique<IndexTexture>(*finest, level->sampler->table(), 256,
                                                  finestAmplitude * finestScale);
    level->indexScale = finestScale;
  }
  level->seconds = timer.seconds();
  return level;
}

}  // namespace meso
