#include "io/checkpoint_stop.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace mesoflow::io {

namespace {

// K of MESOFLOW_STOP_AFTER_CHECKPOINT, or 0 when it is not set.
long long stop_after() {
  const char* text = std::getenv("MESOFLOW_STOP_AFTER_CHECKPOINT");
  if (text == nullptr || *text == '\0') return 0;
  char* end = nullptr;
  const long long k = std::strtoll(text, &end, 10);
  if (*end != '\0' || k < 1)
    throw std::invalid_argument(std::string("MESOFLOW_STOP_AFTER_CHECKPOINT must be a positive integer, got '") + text +
                                "'");
  return k;
}

}  // namespace

void before_checkpoint() {
  static const long long k = stop_after();
  static long long written = 0;
  if (k == 0) return;
  if (written == k) {
    std::fprintf(stderr, "stopped after checkpoint %lld (MESOFLOW_STOP_AFTER_CHECKPOINT)\n", k);
    std::fflush(stderr);
    std::_Exit(stopped_after_checkpoint_status);
  }
  ++written;
}

}  // namespace mesoflow::io
