// Fuzz target: a robot's whole connection into one station: a sequence of messages (fuzz_input.h)
// taken as the station's network input takes them (a HELLO names the robot; an UPDATE's payload
// expanded, its checksum made right (fuzz_input.h), decoded, and refused unless it is that
// robot's, with the message's sequence), and
// every update it lets through handed to one frontend (the scene-graph processor, its sequencing,
// snapshots and checks) and the loop-closure detector, as the station's frontend thread does.
// Whatever the sequence, the frontend refuses what it cannot apply with a reason and keeps going.

#include "fuzz/fuzz_check.h"
#include "fuzz/fuzz_input.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/frontend/loop_closure_detector.h"
#include "hydra_multi/frontend/scene_graph_processor.h"
#include "hydra_multi/net/payload.h"
#include "hydra_multi/net/protocol.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view in(reinterpret_cast<const char*>(data), size);
  SceneGraphProcessor processor;
  LoopClosureDetector detector;
  std::optional<RobotId> robot;  // the connection's, from its HELLO
  for (int messages = 0; !in.empty() && messages < 64; ++messages) {
    auto message = net::decodeMessage(fuzz::takeFrames(in));
    if (!fuzz::decoded(message)) continue;
    const net::Message& m = message.value();
    if (m.type == net::MessageType::kHello) robot = m.robot;
    if (m.type != net::MessageType::kUpdate || !robot) continue;
    auto record = net::expandPayload(m.payload, 64u << 20);
    if (!fuzz::decoded(record)) continue;
    auto update = io::decodeRobotUpdateBinary(fuzz::withChecksum(record.value()));
    if (!fuzz::decoded(update)) continue;
    if (update.value().robot != *robot || update.value().sequence != m.sequence) continue;
    const UpdateReport report = processor.process(update.value());
    if (report.outcome != UpdateOutcome::kApplied && report.message.empty())
      fuzz::fail("an update the frontend did not apply, without a reason");
    detector.update(processor, report.new_keyframes);
  }
  detector.flush(processor);
  return 0;
}
