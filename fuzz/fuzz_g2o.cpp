// Fuzz target: g2o and TORO pose-graph files (`pgo`, `bench-robust`), 2D and 3D: a bad line is
// skipped with a warning naming it, or the file is refused with a reason.

#include "fuzz/fuzz_check.h"
#include "hydra_multi/optim/io/g2o_format.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (auto file = io::parseG2o(text, "fuzz.g2o"); fuzz::decoded(file)) {
    for (const std::string& warning : file.value().warnings)
      if (warning.empty()) fuzz::fail("an empty warning");
  }
  return 0;
}
