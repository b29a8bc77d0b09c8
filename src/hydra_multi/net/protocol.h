#pragma once
// The messages between robots and the station (docs/PROTOCOL.md), without sockets: each message
// is a list of frames; the first is the header "HM", the protocol version and the type, then
// fixed fields, little-endian. decodeMessage checks every frame against its type and never
// trusts a length it has not checked.
//
//   HELLO      robot -> station   header                 | JSON {robot, epoch, layers}
//   WELCOME    station -> robot   header                 | JSON {station, next_sequence,
//                                                           compression}
//   REFUSE     station -> robot   header, epoch, seq, code | reason (text); seq: the update
//                                                      refused, kNoSequence for another message
//   UPDATE     robot -> station   header, epoch, seq     | payload (a .dsgb robot-update record,
//                                                           or a zstd frame of one: payload.h)
//   ACK        station -> robot   header, epoch, seq, next  (update seq is held, and every one
//                                                           before next)
//   HEARTBEAT  both ways          header
//   BYE        both ways          header                 (the robot's mission is over; the
//                                                          station answers with BYE)
//   SNAPSHOT_REQUEST station -> robot header, epoch, next (the station lacks update next and the
//                                                         robot has no way to resend it: send a
//                                                         snapshot of the robot's whole map)

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/robot_id.h"

namespace hydra_multi::net {

inline constexpr uint8_t kProtocolVersion = 1;
/// REFUSE of a message that is not an update.
inline constexpr uint64_t kNoSequence = ~uint64_t{0};

enum class MessageType : uint8_t {
  kHello = 1,
  kWelcome = 2,
  kRefuse = 3,
  kUpdate = 4,
  kAck = 5,
  kHeartbeat = 6,
  kBye = 7,
  kSnapshotRequest = 8,
};
const char* messageTypeName(MessageType type);

/// Why the station refused a message (REFUSE's code; docs/PROTOCOL.md).
enum class RefuseCode : uint8_t {
  kTooLarge = 1,
  kVersion = 2,
  kMalformed = 3,
  kNoHello = 4,  ///< this connection has not said HELLO: say it (again), nothing is dropped
  kWrongRobot = 5,
  kBadPayload = 6,
  kNotStored = 7,
  kStaleEpoch = 8,   ///< a message of an older run of the robot's process than its current one
  kTooFarAhead = 9,  ///< too many updates held beyond a missing one: a snapshot is due first
  /// Not sent: messages above a connection's rate limit are dropped unanswered, and counted so.
  kRateLimited = 10,
};
/// "too_large", "version", ...: the name counted in station.json.
const char* refuseCodeName(RefuseCode code);

struct Message {
  MessageType type = MessageType::kHeartbeat;
  uint64_t epoch = 0;     ///< UPDATE, ACK, HELLO: the robot process's run (changes on restart)
  uint64_t sequence = 0;  ///< UPDATE: its sequence; ACK, REFUSE: the update answered
  /// HELLO: robot and layers it provides.
  RobotId robot;
  uint32_t provided_layers = 0;
  /// WELCOME, ACK, SNAPSHOT_REQUEST: the station holds every update of this robot before it (0:
  /// none).
  uint64_t next_sequence = 0;
  std::string text;                          ///< REFUSE: the reason; WELCOME: the station's name
  RefuseCode code = RefuseCode::kMalformed;  ///< REFUSE
  std::string payload;  ///< UPDATE: the robot update, as one .dsgb record (or a zstd frame of one)
  bool zstd = false;    ///< WELCOME: the station takes zstd-compressed payloads
};

Message hello(RobotId robot, uint64_t epoch, uint32_t provided_layers);
Message welcome(uint64_t next_sequence, bool zstd = true);
Message refuse(RefuseCode code, std::string reason, uint64_t epoch = 0,
               uint64_t sequence = kNoSequence);
Message update(uint64_t epoch, uint64_t sequence, std::string payload);
Message ack(uint64_t epoch, uint64_t sequence, uint64_t next_sequence);
Message snapshotRequest(uint64_t epoch, uint64_t next_sequence);
Message heartbeat();
Message bye();

/// What an UPDATE's message adds to its payload: the header frame (what the bandwidth counts
/// on the wire besides the record).
size_t updateFramingBytes();

/// The frames of a message, in order.
std::vector<std::string> encodeMessage(const Message& message);
/// A message from its frames; an error says what is wrong ("frame 1: HELLO: no robot name").
/// Refused: a frame count or size that does not fit the type, another protocol version, an
/// unknown type, malformed JSON.
Result<Message> decodeMessage(const std::vector<std::string>& frames);

}  // namespace hydra_multi::net
