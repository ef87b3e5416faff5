// The benchmarks' main: the floating-point mode of every meso program (core/floating_point.h),
// then Google Benchmark's own main.
#pragma once

#include "meso/core/floating_point.h"

#include <benchmark/benchmark.h>

#define MESO_BENCHMARK_MAIN()                                         \
  int main(int argc, char** argv) {                                   \
    meso::useFlushToZero();                                           \
    benchmark::Initialize(&argc, argv);                               \
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1; \
    benchmark::RunSpecifiedBenchmarks();                              \
    benchmark::Shutdown();                                            \
    return 0;                                                         \
  }
