// Fuzz target: the binary payloads a robot update, a graph or a graph delta carry, past the
// record's checksum (which random bytes would almost never pass): the input is taken as the
// payload of a robot-update record and of a graph record, and whole as one record of each kind.

#include "fuzz/fuzz_check.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/binary_record.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (auto update = io::decodeRobotUpdatePayload({io::RecordKind::kRobotUpdate, 0, bytes});
      fuzz::decoded(update)) {
    const std::string again = io::encodeRobotUpdateBinary(update.value());
    if (!io::decodeRobotUpdateBinary(again).ok())
      fuzz::fail("a decoded robot update does not decode once encoded again");
  }
  if (auto graph = io::decodeSceneGraphPayload({io::RecordKind::kSceneGraph, 0, bytes});
      fuzz::decoded(graph)) {
    if (!io::decodeSceneGraphBinary(io::encodeSceneGraphBinary(graph.value())).ok())
      fuzz::fail("a decoded graph does not decode once encoded again");
  }
  (void)fuzz::decoded(io::decodeRobotUpdateBinary(bytes));
  (void)fuzz::decoded(io::decodeSceneGraphBinary(bytes));
  if (auto delta = io::decodeGraphDeltaBinary(bytes); fuzz::decoded(delta)) {
    if (!io::decodeGraphDeltaBinary(io::encodeGraphDeltaBinary(delta.value())).ok())
      fuzz::fail("a decoded graph delta does not decode once encoded again");
  }
  return 0;
}
