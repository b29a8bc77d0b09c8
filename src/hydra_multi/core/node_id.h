#pragma once
// NodeId: 64 bits, as Hydra and GTSAM symbols lay them out, with one addition for the station.
//
//   bits 63..56  category character ('O' object, 'p' place, 'R' room, 'B' building, and for agent
//                poses the robot's prefix letter 'a', 'b', ...)
//   bit  55      set on station ids: ids the station gives out, unique across robots
//   bits 54..48  station ids only: the source robot's index
//   bits 47..0   station ids: the index; robot-side ids use bits 54..0 for the index
//
// Robots send robot-side ids, which collide across robots (every robot has an O(0)). The station
// remaps every node to a station id that names its source robot: O(0)@b is robot b's object.
// Readable forms: "O(3)", "p(17)", "a12" (agent: a lowercase letter other than 'p' and the index),
// "O(3)@b" (station id), "#200(3)" (a category byte that is not a letter or digit).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "hydra_multi/core/robot_id.h"

namespace hydra_multi {

class NodeId {
 public:
  static constexpr uint64_t kStationBit = uint64_t{1} << 55;
  static constexpr uint64_t kMaxRobotIndex = (uint64_t{1} << 55) - 1;
  static constexpr uint64_t kMaxStationIndex = (uint64_t{1} << 48) - 1;

  constexpr NodeId() = default;
  /// Wraps a raw 64-bit key (e.g. from a file) unchanged.
  constexpr explicit NodeId(uint64_t value) : value_(value) {}
  /// A robot-side id; index must be <= kMaxRobotIndex (checked: throws std::out_of_range).
  NodeId(char category, uint64_t index);
  /// A station id naming its source robot; index must be <= kMaxStationIndex (throws otherwise).
  static NodeId station(char category, RobotId source, uint64_t index);
  /// Parses a readable form produced by str(); nullopt when it is not one.
  static std::optional<NodeId> parse(const std::string& text);

  constexpr uint64_t value() const { return value_; }
  constexpr char category() const { return static_cast<char>(value_ >> 56); }
  constexpr bool isStation() const { return (value_ & kStationBit) != 0; }
  /// The index inside the category (without the robot bits for station ids).
  constexpr uint64_t index() const {
    return isStation() ? (value_ & kMaxStationIndex) : (value_ & kMaxRobotIndex);
  }
  /// The source robot of a station id; nullopt for robot-side ids.
  std::optional<RobotId> sourceRobot() const;
  /// Readable form, e.g. "O(3)", "a12", "O(3)@b".
  std::string str() const;

  constexpr bool operator==(NodeId other) const { return value_ == other.value_; }
  constexpr bool operator!=(NodeId other) const { return value_ != other.value_; }
  constexpr bool operator<(NodeId other) const { return value_ < other.value_; }

 private:
  uint64_t value_ = 0;
};

}  // namespace hydra_multi

template <>
struct std::hash<hydra_multi::NodeId> {
  size_t operator()(hydra_multi::NodeId id) const noexcept {
    return std::hash<uint64_t>{}(id.value());
  }
};
