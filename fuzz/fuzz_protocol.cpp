// Fuzz target: one message of the station's protocol (docs/PROTOCOL.md) as its frames
// (fuzz_input.h), decoded as the station and a robot decode it; an UPDATE's payload expanded
// (zstd, within the 64 MB limit) and decoded as a robot-update record. A decoded message encodes
// to frames that decode again.

#include "fuzz/fuzz_check.h"
#include "fuzz/fuzz_input.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/net/payload.h"
#include "hydra_multi/net/protocol.h"

using namespace hydra_multi;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view in(reinterpret_cast<const char*>(data), size);
  const std::vector<std::string> frames = fuzz::takeFrames(in);
  auto message = net::decodeMessage(frames);
  if (!fuzz::decoded(message)) return 0;
  if (!net::decodeMessage(net::encodeMessage(message.value())).ok())
    fuzz::fail("a decoded message does not decode once encoded again");
  if (message.value().type != net::MessageType::kUpdate) return 0;
  auto record = net::expandPayload(message.value().payload, 64u << 20);
  if (!fuzz::decoded(record)) return 0;
  (void)fuzz::decoded(io::decodeRobotUpdateBinary(record.value()));
  (void)fuzz::decoded(io::decodeRobotUpdateBinary(fuzz::withChecksum(record.value())));
  return 0;
}
