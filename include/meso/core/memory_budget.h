// Memory estimated before it is allocated: a job whose estimate exceeds the limit is refused with
// the estimate and the key that caused it, instead of running to bad_alloc after gigabytes (or for
// minutes). The limit is a command's (--memory-limit; default half of physical memory): it is
// passed down to whatever reads or allocates (scene loading, image decoding, table building), never
// held in a global.
#pragma once

#include <cstdint>
#include <string>

namespace meso {

uint64_t physicalMemoryBytes();

// Geometry per triangle, Embree's BVH included. Measured: about 70 MiB per million displaced
// micropolygons; with margin.
inline constexpr double kBytesPerMicropolygon = 96.0;

// Half of physical memory (4 GiB when it cannot be read).
uint64_t defaultMemoryLimitBytes();

// "1234.5 MiB".
std::string formatMib(double bytes);

// Throws meso::Error("WHERE: KEY: needs an estimated N MiB (WHAT), more than the memory limit of
// M MiB (--memory-limit)") when bytes > limitBytes. `where` may be empty.
void requireMemoryWithin(uint64_t limitBytes, double bytes, const std::string& where,
                         const std::string& key, const std::string& what);

}  // namespace meso
