// Fuzz target: Spark-DSG's binary form, as a file (header and graph, `dsg.sparkdsg`) and as the
// ZeroMQ wire payload a Hydra robot publishes, in each version the codec reads (the first byte
// picks it); what decodes becomes one of our scene graphs or is refused with a reason, and
// encodes to bytes that decode again.

#include "fuzz/fuzz_check.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/io/spark_graph.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (auto file = io::sceneGraphFromSparkFile(std::string(bytes)); fuzz::decoded(file)) {
    if (!io::sceneGraphFromSparkFile(io::sceneGraphToSparkFile(file.value())).ok())
      fuzz::fail("a decoded Spark-DSG file does not decode once encoded again");
  }
  if (size == 0) return 0;
  static const io::spark::Version kVersions[] = {{1, 0, 2}, {1, 0, 3}, {1, 0, 4}, {1, 0, 5},
                                                 {1, 0, 6}, {1, 1, 0}, {1, 1, 1}, {1, 1, 2},
                                                 {1, 1, 3}, {1, 1, 4}};
  const io::spark::Version version = kVersions[data[0] % std::size(kVersions)];
  if (!io::spark::unsupported(version).empty()) return 0;
  auto wire = io::spark::decodeWire(bytes.substr(1), version);
  if (!fuzz::decoded(wire)) return 0;
  if (!io::spark::decodeWire(io::spark::encodeWire(wire.value(), version), version).ok())
    fuzz::fail("a decoded Spark-DSG wire graph does not decode once encoded again");
  (void)fuzz::decoded(io::sceneGraphFromSpark(wire.value()));
  return 0;
}
