// Google Benchmark entry point shared by the mesoflow benchmarks: Kokkos lives for the whole run
// and its configuration (version, backends, threads) is recorded in the JSON context.
#include <benchmark/benchmark.h>

#include "kernels/common/kokkos_compat.hpp"

int main(int argc, char** argv) {
  mesoflow::initialize_kokkos(-1);
  ::benchmark::Initialize(&argc, argv);
  ::benchmark::AddCustomContext("kokkos", mesoflow::kokkos_configuration());
  ::benchmark::AddCustomContext("threads", std::to_string(mesoflow::concurrency<Kokkos::DefaultExecutionSpace>()));
  if (::benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  ::benchmark::RunSpecifiedBenchmarks();
  ::benchmark::Shutdown();
  Kokkos::finalize();
  return 0;
}
