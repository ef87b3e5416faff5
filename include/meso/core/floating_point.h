// The floating-point mode meso computes in: flush-to-zero and denormals-are-zero (MXCSR FTZ and
// DAZ), as Embree asks of the threads that trace. Every program sets it on its main thread before
// its first parallel loop: TBB's tasks then run in the mode their arena captured from that thread,
// so a table or an image has the same bits whichever thread computes which part of it.
#pragma once

namespace meso {

// Sets flush-to-zero and denormals-are-zero on the calling thread (a no-op without SSE).
void useFlushToZero();

// Whether the calling thread flushes denormals to zero (always false without SSE).
bool flushesToZero();

}  // namespace meso
