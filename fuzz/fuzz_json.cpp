// Fuzz target: our JSON formats, a scene graph and a robot update (`convert`, `info`, dataset
// files); what decodes encodes again and decodes.

#include "fuzz/fuzz_check.h"
#include "hydra_multi/dsg/io/json_format.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (auto graph = io::sceneGraphFromJson(text); fuzz::decoded(graph)) {
    if (!io::sceneGraphFromJson(io::sceneGraphToJson(graph.value(), true)).ok())
      fuzz::fail("a decoded JSON graph does not decode once encoded again");
  }
  if (auto update = io::robotUpdateFromJson(text); fuzz::decoded(update)) {
    if (!io::robotUpdateFromJson(io::robotUpdateToJson(update.value(), true)).ok())
      fuzz::fail("a decoded JSON robot update does not decode once encoded again");
  }
  return 0;
}
