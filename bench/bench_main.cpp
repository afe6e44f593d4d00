// Entry point: the KDL peers live in a separate shared library and register at run time.
#include <benchmark/benchmark.h>

#include "kdl_peer.hpp"

int main(int argc, char** argv) {
  lowpair_bench::registerKdlBenchmarks(&lowpair_bench::robotCase);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
