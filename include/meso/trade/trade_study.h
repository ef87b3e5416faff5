// `meso trade` as a library: Becker & Max 1993's promise, measured. The paper's D (our
// render.transition.D, its c) trades accuracy for speed; the study renders a full-displacement
// reference refined until it converges (reference_study.h), then every configuration of the
// hybrid and of displacement alone (configuration.h), each measured (measured_render.h) and
// compared with the reference (image_errors.h); optionally the temporal stability of the default
// hybrid near its thresholds (temporal_stability.h).
#pragma once

#include "meso/core/memory_budget.h"
#include "meso/scene/scene.h"
#include "meso/trade/configuration.h"
#include "meso/trade/measured_render.h"
#include "meso/trade/reference_cache.h"
#include "meso/trade/reference_study.h"
#include "meso/trade/trade_result.h"

#include <atomic>
#include <vector>

namespace meso::trade {

struct TradeSettings {
  ReferenceBudget reference;
  SweepGrid grid;
  bool temporal = false;  // keep the default hybrid's films for temporalBands
  bool quiet = false;     // no progress on stderr
  uint64_t memoryLimitBytes = defaultMemoryLimitBytes();  // PrepareOptions::memoryLimitBytes
};

struct TradeStudy {
  ReferenceStudy reference;
  std::vector<TradeResult> results;  // reference levels first (the last one named "reference")
  MeasuredRender defaultHybrid;      // with its films when settings.temporal
};

// Throws meso::Error on bad settings (naming the command-line option), meso::Interrupted when
// `cancel` is set.
void validateTradeSettings(const TradeSettings& settings);

// Every configuration of `scene` through `cameras`.
TradeStudy runTradeStudy(const Scene& scene, const std::vector<CameraSettings>& cameras,
                         const TradeSettings& settings, const ReferenceCache& cache,
                         const std::atomic<bool>* cancel);

}  // namespace meso::trade
