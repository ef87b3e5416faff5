// Peak memory per configuration of `meso trade`: VmHWM, reset between configurations.
#pragma once

namespace meso::trade {

// Returns freed heap to the system (malloc_trim) and resets VmHWM by writing "5" to
// /proc/self/clear_refs (Linux >= 4.0), so that core/timer.h's peakRssMib() afterwards is the peak
// since this call; false where that file is not writable (then the peak is process-wide).
bool resetPeakRss();

}  // namespace meso::trade
