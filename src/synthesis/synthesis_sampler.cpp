// Kautz et al. 2001, section 4: x_n = M^-1(G(r1)), y_n = C^-1(G(r2) | x_n).
#include "meso/synthesis/synthesis_sampler.h"

namespace meso {

SynthesisSampler::SynthesisSampler(const Ndf& ndf, const SynthesisOptions& options)
    : ndf_(&ndf),
      turbulence_(options.turbulence),
      cdf_(turbulence_, options.cdf),
      table_(ndf, options.table) {}

}  // namespace meso
