// The protocol's messages: every type round-trips through its frames; frames that do not fit
// their type, another version, unknown types and malformed bodies are refused with a message
// naming the frame; mutated frames never crash the decoder.

#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/net/protocol.h"
#include "support/mutations.h"

namespace hydra_multi::net {
namespace {

const RobotId kB(1);

Message roundTrip(const Message& m) {
  auto back = decodeMessage(encodeMessage(m));
  EXPECT_TRUE(back.ok()) << back.error();
  return back ? back.value() : Message{};
}

// Every field a type carries comes back.
TEST(Protocol, EveryTypeRoundTrips) {
  const Message h = roundTrip(hello(kB, 77, kProvidesAgents | kProvidesMesh));
  EXPECT_EQ(h.type, MessageType::kHello);
  EXPECT_EQ(h.robot, kB);
  EXPECT_EQ(h.epoch, 77u);
  EXPECT_EQ(h.provided_layers, kProvidesAgents | kProvidesMesh);
  EXPECT_EQ(roundTrip(welcome(12)).next_sequence, 12u);
  const Message r = roundTrip(refuse(RefuseCode::kWrongRobot, "no", 5, 9));
  EXPECT_EQ(r.code, RefuseCode::kWrongRobot);
  EXPECT_EQ(r.text, "no");
  EXPECT_EQ(r.epoch, 5u);
  EXPECT_EQ(r.sequence, 9u);
  EXPECT_EQ(roundTrip(refuse(RefuseCode::kNoHello, "no")).sequence, kNoSequence);
  const Message u = roundTrip(update(3, 41, std::string("pay\0load", 8)));
  EXPECT_EQ(u.epoch, 3u);
  EXPECT_EQ(u.sequence, 41u);
  EXPECT_EQ(u.payload, std::string("pay\0load", 8));
  const Message a = roundTrip(ack(3, 41, 40));
  EXPECT_EQ(a.sequence, 41u);
  EXPECT_EQ(a.next_sequence, 40u);
  EXPECT_EQ(roundTrip(heartbeat()).type, MessageType::kHeartbeat);
  EXPECT_EQ(roundTrip(bye()).type, MessageType::kBye);
  const Message s = roundTrip(snapshotRequest(3, 17));
  EXPECT_EQ(s.type, MessageType::kSnapshotRequest);
  EXPECT_EQ(s.epoch, 3u);
  EXPECT_EQ(s.next_sequence, 17u);
  EXPECT_EQ(encodeMessage(snapshotRequest(3, 17)).front().size(), 20u);  // header and two fields
  EXPECT_EQ(updateFramingBytes(), encodeMessage(update(3, 41, "payload")).front().size());
}

std::string refusal(const std::vector<std::string>& frames) {
  auto m = decodeMessage(frames);
  EXPECT_FALSE(m.ok());
  return m.ok() ? "" : m.error();
}

// What does not fit is refused, and the message says where.
TEST(Protocol, RefusesWhatDoesNotFit) {
  std::vector<std::string> frames = encodeMessage(update(1, 2, "x"));
  EXPECT_EQ(refusal({}), "an empty message");
  EXPECT_EQ(refusal({"GET / HTTP/1.1"}), "frame 0: not a hydra-multi message (no \"HM\" header)");
  std::string v2 = frames[0];
  v2[2] = 2;
  EXPECT_EQ(refusal({v2, "x"}), "frame 0: protocol version 2, this station speaks 1");
  std::string unknown = frames[0];
  unknown[3] = 99;
  EXPECT_EQ(refusal({unknown, "x"}), "frame 0: unknown message type 99");
  EXPECT_EQ(refusal({frames[0].substr(0, 10), "x"}),
            "frame 0: UPDATE: a header of 10 bytes, not 20");
  EXPECT_EQ(refusal({frames[0]}), "UPDATE: 1 frames, not 2");
  std::vector<std::string> refused = encodeMessage(refuse(RefuseCode::kVersion, "x"));
  refused[0].back() = 42;
  EXPECT_EQ(refusal(refused), "frame 0: REFUSE: unknown refusal code 42");
  const std::string hello_header = encodeMessage(hello(kB, 1, 0))[0];
  EXPECT_EQ(refusal({hello_header, "{"}), "frame 1: HELLO: not a JSON object");
  EXPECT_EQ(refusal({hello_header, R"({"epoch": 1})"}), "frame 1: HELLO: no robot name");
  EXPECT_EQ(refusal({hello_header, R"({"robot": "?", "epoch": 1})"}),
            "frame 1: HELLO: unknown robot \"?\"");
  EXPECT_EQ(refusal({hello_header, R"({"robot": "a", "epoch": -1})"}), "frame 1: HELLO: no epoch");
  EXPECT_EQ(refusal({hello_header, R"({"robot": "a", "epoch": 1, "layers": ["sonar"]})"}),
            "frame 1: HELLO: unknown layer \"sonar\"");
  EXPECT_EQ(refusal({hello_header, std::string(5000, ' ')}),
            "frame 1: HELLO: 5000 bytes of JSON, more than 4096");
}

// 20000 mutations of valid messages' frames: each decodes or is refused, never throws.
TEST(Protocol, MutatedFramesNeverCrash) {
  const std::vector<std::vector<std::string>> valid = {
      encodeMessage(hello(kB, 7, kProvidesAll)),
      encodeMessage(welcome(3)),
      encodeMessage(refuse(RefuseCode::kMalformed, "why", 1, 2)),
      encodeMessage(update(1, 2, "payload")),
      encodeMessage(ack(1, 2, 3)),
      encodeMessage(heartbeat()),
      encodeMessage(bye())};
  std::mt19937 rng(19);
  size_t refused = 0;
  for (int i = 0; i < 20000; ++i) {
    std::vector<std::string> frames = valid[rng() % valid.size()];
    std::string& frame = frames[rng() % frames.size()];
    frame = testing::mutateBytes(frame, rng);
    Result<Message> m = Error{""};
    ASSERT_NO_THROW(m = decodeMessage(frames));
    if (!m) {
      ++refused;
      ASSERT_FALSE(m.error().empty());
    }
  }
  EXPECT_GT(refused, 1000u);
}

}  // namespace
}  // namespace hydra_multi::net
