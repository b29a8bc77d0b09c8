// Fuzz target: a .dsgb file (a robot's stream, a graph), read record by record as `run` and
// `info` read one: every record's checksum, version and kind checked, a damaged one skipped to the
// next magic bytes, each record's payload decoded by its kind. What decodes encodes again and
// decodes to the same record.

#include "fuzz/fuzz_check.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/binary_record.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  io::RecordReader reader(std::string_view(reinterpret_cast<const char*>(data), size));
  for (int records = 0; records < 1000; ++records) {
    auto next = reader.next();
    if (!fuzz::decoded(next)) {
      if (!reader.resynchronize()) break;
      continue;
    }
    if (!next.value()) break;
    const io::RecordView& record = *next.value();
    if (record.kind == io::RecordKind::kRobotUpdate) {
      auto update = io::decodeRobotUpdatePayload(record);
      if (fuzz::decoded(update)) {
        const std::string again = io::encodeRobotUpdateBinary(update.value());
        auto twice = io::decodeRobotUpdateBinary(again);
        if (!twice.ok()) fuzz::fail("a decoded robot update does not decode once encoded again");
        if (io::encodeRobotUpdateBinary(twice.value()) != again)
          fuzz::fail("a robot update's round trip changed it");
      }
    } else if (record.kind == io::RecordKind::kSceneGraph) {
      auto graph = io::decodeSceneGraphPayload(record);
      if (fuzz::decoded(graph)) {
        const std::string again = io::encodeSceneGraphBinary(graph.value());
        auto twice = io::decodeSceneGraphBinary(again);
        if (!twice.ok()) fuzz::fail("a decoded graph does not decode once encoded again");
        if (io::encodeSceneGraphBinary(twice.value()) != again)
          fuzz::fail("a graph's round trip changed it");
      }
    }
  }
  return 0;
}
