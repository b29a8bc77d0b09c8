#include "hydra_multi/net/protocol.h"

#include <nlohmann/json.hpp>

#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"
#include "hydra_multi/dsg/robot_update.h"

namespace hydra_multi::net {
namespace {

using Json = nlohmann::json;

constexpr size_t kHeaderBytes = 4;      // "HM", version, type
constexpr size_t kMaxJsonBytes = 4096;  // HELLO, WELCOME
constexpr size_t kMaxReasonBytes = 4096;

// Bytes of fixed fields after the 4 header bytes: UPDATE epoch and sequence; REFUSE those and its
// code; ACK those and the next sequence.
size_t fixedFieldBytes(MessageType type) {
  if (type == MessageType::kUpdate) return 16;
  if (type == MessageType::kRefuse) return 17;
  if (type == MessageType::kAck) return 24;
  if (type == MessageType::kSnapshotRequest) return 16;
  return 0;
}

// Frames after the header that a type has.
size_t bodyFrames(MessageType type) {
  switch (type) {
    case MessageType::kHello:
    case MessageType::kWelcome:
    case MessageType::kRefuse:
    case MessageType::kUpdate:
      return 1;
    default:
      return 0;
  }
}

std::string header(const Message& m) {
  io::ByteWriter w;
  w.raw("HM");
  w.u8(kProtocolVersion);
  w.u8(static_cast<uint8_t>(m.type));
  if (m.type == MessageType::kSnapshotRequest) {
    w.u64(m.epoch);
    w.u64(m.next_sequence);
  } else if (fixedFieldBytes(m.type) > 0) {
    w.u64(m.epoch);
    w.u64(m.sequence);
  }
  if (m.type == MessageType::kAck) w.u64(m.next_sequence);
  if (m.type == MessageType::kRefuse) w.u8(static_cast<uint8_t>(m.code));
  return w.release();
}

Json layersJson(uint32_t layers) {
  Json names = Json::array();
  for (uint32_t bit = 1; bit <= kProvidesAll; bit <<= 1) {
    if (layers & bit) names.push_back(providedLayerName(bit));
  }
  return names;
}

uint32_t layersFromJson(const Json& names) {
  if (!names.is_array()) throw io::DecodeError("\"layers\" is not a list");
  uint32_t layers = 0;
  for (const Json& name : names) {
    bool known = false;
    for (uint32_t bit = 1; bit <= kProvidesAll; bit <<= 1) {
      if (name.is_string() && name.get<std::string>() == providedLayerName(bit)) {
        layers |= bit;
        known = true;
      }
    }
    if (!known) throw io::DecodeError("unknown layer " + name.dump());
  }
  return layers;
}

Json parseBody(const std::string& frame) {
  if (frame.size() > kMaxJsonBytes)
    throw io::DecodeError(std::to_string(frame.size()) + " bytes of JSON, more than " +
                          std::to_string(kMaxJsonBytes));
  Json j = Json::parse(frame, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw io::DecodeError("not a JSON object");
  return j;
}

}  // namespace

const char* messageTypeName(MessageType type) {
  switch (type) {
    case MessageType::kHello:
      return "HELLO";
    case MessageType::kWelcome:
      return "WELCOME";
    case MessageType::kRefuse:
      return "REFUSE";
    case MessageType::kUpdate:
      return "UPDATE";
    case MessageType::kAck:
      return "ACK";
    case MessageType::kHeartbeat:
      return "HEARTBEAT";
    case MessageType::kBye:
      return "BYE";
    case MessageType::kSnapshotRequest:
      return "SNAPSHOT_REQUEST";
  }
  return "?";
}

const char* refuseCodeName(RefuseCode code) {
  switch (code) {
    case RefuseCode::kTooLarge:
      return "too_large";
    case RefuseCode::kVersion:
      return "version";
    case RefuseCode::kMalformed:
      return "malformed";
    case RefuseCode::kNoHello:
      return "no_hello";
    case RefuseCode::kWrongRobot:
      return "wrong_robot";
    case RefuseCode::kBadPayload:
      return "bad_payload";
    case RefuseCode::kNotStored:
      return "not_stored";
    case RefuseCode::kStaleEpoch:
      return "stale_epoch";
    case RefuseCode::kTooFarAhead:
      return "too_far_ahead";
    case RefuseCode::kRateLimited:
      return "rate_limited";
  }
  return "?";
}

Message hello(RobotId robot, uint64_t epoch, uint32_t provided_layers) {
  Message m;
  m.type = MessageType::kHello;
  m.robot = robot;
  m.epoch = epoch;
  m.provided_layers = provided_layers;
  return m;
}

Message welcome(uint64_t next_sequence, bool zstd) {
  Message m;
  m.type = MessageType::kWelcome;
  m.next_sequence = next_sequence;
  m.text = "hydra-multi";
  m.zstd = zstd;
  return m;
}

Message refuse(RefuseCode code, std::string reason, uint64_t epoch, uint64_t sequence) {
  Message m;
  m.type = MessageType::kRefuse;
  m.code = code;
  m.text = std::move(reason);
  m.epoch = epoch;
  m.sequence = sequence;
  return m;
}

Message update(uint64_t epoch, uint64_t sequence, std::string payload) {
  Message m;
  m.type = MessageType::kUpdate;
  m.epoch = epoch;
  m.sequence = sequence;
  m.payload = std::move(payload);
  return m;
}

Message ack(uint64_t epoch, uint64_t sequence, uint64_t next_sequence) {
  Message m;
  m.type = MessageType::kAck;
  m.epoch = epoch;
  m.sequence = sequence;
  m.next_sequence = next_sequence;
  return m;
}

Message snapshotRequest(uint64_t epoch, uint64_t next_sequence) {
  Message m;
  m.type = MessageType::kSnapshotRequest;
  m.epoch = epoch;
  m.next_sequence = next_sequence;
  return m;
}

Message heartbeat() { return Message{}; }

Message bye() {
  Message m;
  m.type = MessageType::kBye;
  return m;
}

size_t updateFramingBytes() { return kHeaderBytes + fixedFieldBytes(MessageType::kUpdate); }

std::vector<std::string> encodeMessage(const Message& m) {
  std::vector<std::string> frames = {header(m)};
  switch (m.type) {
    case MessageType::kHello:
      frames.push_back(Json{
          {"robot", m.robot.str()}, {"epoch", m.epoch}, {"layers", layersJson(m.provided_layers)}}
                           .dump());
      break;
    case MessageType::kWelcome:
      frames.push_back(Json{{"station", m.text},
                            {"next_sequence", m.next_sequence},
                            {"compression", m.zstd ? Json::array({"zstd"}) : Json::array()}}
                           .dump());
      break;
    case MessageType::kRefuse:
      frames.push_back(m.text);
      break;
    case MessageType::kUpdate:
      frames.push_back(m.payload);
      break;
    default:
      break;
  }
  return frames;
}

Result<Message> decodeMessage(const std::vector<std::string>& frames) {
  if (frames.empty()) return Error{"an empty message"};
  const std::string& head = frames.front();
  if (head.size() < kHeaderBytes || head.compare(0, 2, "HM") != 0)
    return Error{"frame 0: not a hydra-multi message (no \"HM\" header)"};
  const uint8_t version = static_cast<uint8_t>(head[2]);
  if (version != kProtocolVersion)
    return Error{"frame 0: protocol version " + std::to_string(version) + ", this station speaks " +
                 std::to_string(kProtocolVersion)};
  const uint8_t type = static_cast<uint8_t>(head[3]);
  if (type < static_cast<uint8_t>(MessageType::kHello) ||
      type > static_cast<uint8_t>(MessageType::kSnapshotRequest))
    return Error{"frame 0: unknown message type " + std::to_string(type)};
  Message m;
  m.type = static_cast<MessageType>(type);
  const std::string name = messageTypeName(m.type);
  const size_t header_bytes = kHeaderBytes + fixedFieldBytes(m.type);
  if (head.size() != header_bytes)
    return Error{"frame 0: " + name + ": a header of " + std::to_string(head.size()) +
                 " bytes, not " + std::to_string(header_bytes)};
  if (frames.size() != 1 + bodyFrames(m.type))
    return Error{name + ": " + std::to_string(frames.size()) + " frames, not " +
                 std::to_string(1 + bodyFrames(m.type))};
  try {  // the header's fixed fields
    if (fixedFieldBytes(m.type) > 0) {
      io::ByteReader r(std::string_view(head).substr(kHeaderBytes), kHeaderBytes);
      m.epoch = r.u64("epoch");
      if (m.type == MessageType::kSnapshotRequest)
        m.next_sequence = r.u64("next sequence");
      else
        m.sequence = r.u64("sequence");
      if (m.type == MessageType::kAck) m.next_sequence = r.u64("next sequence");
      if (m.type == MessageType::kRefuse) {
        const uint8_t code = r.u8("code");
        if (code < static_cast<uint8_t>(RefuseCode::kTooLarge) ||
            code > static_cast<uint8_t>(RefuseCode::kRateLimited))
          throw io::DecodeError("unknown refusal code " + std::to_string(code));
        m.code = static_cast<RefuseCode>(code);
      }
    }
  } catch (const io::DecodeError& e) {
    return Error{"frame 0: " + name + ": " + e.what()};
  }
  try {  // the body
    switch (m.type) {
      case MessageType::kHello: {
        const Json j = parseBody(frames[1]);
        if (!j.contains("robot") || !j["robot"].is_string()) throw io::DecodeError("no robot name");
        const auto robot = RobotId::parse(j["robot"].get<std::string>());
        if (!robot) throw io::DecodeError("unknown robot " + j["robot"].dump());
        if (!j.contains("epoch") || !j["epoch"].is_number_unsigned())
          throw io::DecodeError("no epoch");
        m.robot = *robot;
        m.epoch = j["epoch"].get<uint64_t>();
        m.provided_layers = layersFromJson(j.value("layers", Json::array()));
        break;
      }
      case MessageType::kWelcome: {
        const Json j = parseBody(frames[1]);
        if (!j.contains("next_sequence") || !j["next_sequence"].is_number_unsigned())
          throw io::DecodeError("no next_sequence");
        m.next_sequence = j["next_sequence"].get<uint64_t>();
        m.text = j.value("station", "");
        if (j.contains("compression")) {  // what UPDATE payloads may be compressed with
          if (!j["compression"].is_array()) throw io::DecodeError("\"compression\" is not a list");
          for (const Json& name : j["compression"]) m.zstd |= name == "zstd";
        }
        break;
      }
      case MessageType::kRefuse:
        if (frames[1].size() > kMaxReasonBytes) throw io::DecodeError("a reason too long");
        m.text = frames[1];
        break;
      case MessageType::kUpdate:
        m.payload = frames[1];
        break;
      default:
        break;
    }
  } catch (const io::DecodeError& e) {
    return Error{"frame 1: " + name + ": " + e.what()};
  } catch (const nlohmann::json::exception& e) {
    return Error{"frame 1: " + name + ": " + e.what()};
  }
  return m;
}

}  // namespace hydra_multi::net
