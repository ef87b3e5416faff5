// MESO_DCHECK(cond, msg): an internal invariant of the library (an index in range, a value the code
// relies on being finite), not a check of input: input is checked where it enters and reported as
// meso::Error. On in Debug builds (NDEBUG undefined) and wherever MESO_ENABLE_DCHECK is defined
// (the sanitizer suite, -DMESO_DCHECK=ON); compiled out otherwise, so a Release build neither
// evaluates `cond` nor pays for it. A failed check prints "FILE:LINE: MESO_DCHECK(cond) failed:
// msg" on stderr and aborts.
#pragma once

#if defined(MESO_ENABLE_DCHECK) || !defined(NDEBUG)
#define MESO_DCHECK_IS_ON 1  // whether MESO_DCHECK is compiled in where this header is included
#else
#define MESO_DCHECK_IS_ON 0
#endif

namespace meso {

// Prints the failed check and aborts (the body of a failed MESO_DCHECK).
[[noreturn]] void dcheckFailed(const char* file, int line, const char* condition,
                               const char* message);

}  // namespace meso

#if MESO_DCHECK_IS_ON
#define MESO_DCHECK(cond, msg) \
  ((cond) ? static_cast<void>(0) : ::meso::dcheckFailed(__FILE__, __LINE__, #cond, msg))
#else
// Unevaluated: the condition still has to compile, and its variables count as used.
#define MESO_DCHECK(cond, msg) static_cast<void>(sizeof(!(cond)))
#endif
