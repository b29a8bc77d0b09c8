#include "hydra_multi/core/node_id.h"

#include <cctype>
#include <stdexcept>

namespace hydra_multi {
namespace {

bool isAgentStyle(char category) { return category >= 'a' && category <= 'z' && category != 'p'; }

bool isPrintableCategory(char category) {
  return std::isalnum(static_cast<unsigned char>(category)) != 0;
}

// Parses a decimal number that fills text[begin, end); nullopt on anything else or overflow.
std::optional<uint64_t> parseDecimal(const std::string& text, size_t begin, size_t end) {
  if (begin >= end || end - begin > 20) return std::nullopt;
  uint64_t value = 0;
  for (size_t i = begin; i < end; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i]))) return std::nullopt;
    const uint64_t digit = static_cast<uint64_t>(text[i] - '0');
    if (value > (UINT64_MAX - digit) / 10) return std::nullopt;
    value = value * 10 + digit;
  }
  return value;
}

}  // namespace

NodeId::NodeId(char category, uint64_t index) {
  if (index > kMaxRobotIndex) throw std::out_of_range("NodeId index too large for a robot-side id");
  value_ = (static_cast<uint64_t>(static_cast<uint8_t>(category)) << 56) | index;
}

NodeId NodeId::station(char category, RobotId source, uint64_t index) {
  if (index > kMaxStationIndex) throw std::out_of_range("NodeId index too large for a station id");
  if (!source.isValid()) throw std::out_of_range("NodeId::station: invalid robot");
  return NodeId((static_cast<uint64_t>(static_cast<uint8_t>(category)) << 56) | kStationBit |
                (static_cast<uint64_t>(source.index()) << 48) | index);
}

std::optional<RobotId> NodeId::sourceRobot() const {
  if (!isStation()) return std::nullopt;
  const RobotId robot(static_cast<uint8_t>((value_ >> 48) & 0x7F));
  if (!robot.isValid()) return std::nullopt;
  return robot;
}

std::string NodeId::str() const {
  const char c = category();
  std::string text;
  if (isAgentStyle(c)) {
    text = std::string(1, c) + std::to_string(index());
  } else if (isPrintableCategory(c)) {
    text = std::string(1, c) + "(" + std::to_string(index()) + ")";
  } else {
    text = "#" + std::to_string(static_cast<uint8_t>(c)) + "(" + std::to_string(index()) + ")";
  }
  if (isStation()) {
    const auto robot = sourceRobot();
    text += "@" + (robot ? robot->str() : std::string("?"));
  }
  return text;
}

std::optional<NodeId> NodeId::parse(const std::string& text) {
  if (text.empty()) return std::nullopt;
  // Split off the station suffix "@r".
  std::string body = text;
  std::optional<RobotId> robot;
  if (const size_t at = text.find('@'); at != std::string::npos) {
    robot = RobotId::parse(text.substr(at + 1));
    if (!robot) return std::nullopt;
    body = text.substr(0, at);
  }
  // Category: one character, or "#<byte>".
  char category = 0;
  size_t rest = 1;
  if (body[0] == '#') {
    const size_t open = body.find('(');
    if (open == std::string::npos) return std::nullopt;
    const auto byte = parseDecimal(body, 1, open);
    if (!byte || *byte > 255 || isPrintableCategory(static_cast<char>(*byte))) return std::nullopt;
    category = static_cast<char>(*byte);
    rest = open;
  } else {
    category = body[0];
    if (!isPrintableCategory(category)) return std::nullopt;
  }
  std::optional<uint64_t> index;
  if (rest < body.size() && body[rest] == '(') {
    if (body.back() != ')' || isAgentStyle(category)) return std::nullopt;
    index = parseDecimal(body, rest + 1, body.size() - 1);
  } else {
    if (!isAgentStyle(category)) return std::nullopt;
    index = parseDecimal(body, rest, body.size());
  }
  if (!index) return std::nullopt;
  if (robot) {
    if (*index > kMaxStationIndex) return std::nullopt;
    return station(category, *robot, *index);
  }
  if (*index > kMaxRobotIndex) return std::nullopt;
  return NodeId(category, *index);
}

}  // namespace hydra_multi
