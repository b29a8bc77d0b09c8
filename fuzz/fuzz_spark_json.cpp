// Fuzz target: Spark-DSG's JSON graph files (Hydra's `dsg.json`), as `convert` and `info` read
// them; what decodes is written as Spark-DSG JSON again and decodes.

#include "fuzz/fuzz_check.h"
#include "hydra_multi/dsg/io/spark_json.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (auto graph = io::sceneGraphFromSparkJson(text); fuzz::decoded(graph)) {
    if (!io::sceneGraphFromSparkJson(io::sceneGraphToSparkJson(graph.value())).ok())
      fuzz::fail("a decoded Spark-DSG JSON graph does not decode once encoded again");
  }
  return 0;
}
