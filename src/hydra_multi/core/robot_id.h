#pragma once
// RobotId: the index of a robot in a team (0, 1, 2, ...). Its one-letter name is the prefix of its
// agent (keyframe) node ids, as in Hydra and GTSAM symbols: robot 0 is 'a', robot 1 is 'b', ...
// The letter 'p' is skipped because Hydra uses it for places, so robot 15 is 'q' and robot 24 'z'.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace hydra_multi {

class RobotId {
 public:
  /// The number of robots that have a letter of their own.
  static constexpr int kMaxRobots = 25;

  constexpr RobotId() = default;
  /// Robot number `index`; valid for 0 <= index < kMaxRobots (see isValid()).
  constexpr explicit RobotId(uint8_t index) : index_(index) {}

  /// The robot whose agent prefix is `letter` ('a' -> 0, ..., 'o' -> 14, 'q' -> 15, ...).
  static std::optional<RobotId> fromPrefix(char letter);
  /// The robot named `name` (its one-letter form, e.g. "b").
  static std::optional<RobotId> parse(const std::string& name);

  constexpr uint8_t index() const { return index_; }
  constexpr bool isValid() const { return index_ < kMaxRobots; }
  /// The agent prefix letter of this robot.
  char prefix() const;
  /// Readable form: the prefix letter, e.g. "b".
  std::string str() const { return std::string(1, prefix()); }

  constexpr bool operator==(RobotId other) const { return index_ == other.index_; }
  constexpr bool operator!=(RobotId other) const { return index_ != other.index_; }
  constexpr bool operator<(RobotId other) const { return index_ < other.index_; }

 private:
  uint8_t index_ = 0;
};

}  // namespace hydra_multi

template <>
struct std::hash<hydra_multi::RobotId> {
  size_t operator()(hydra_multi::RobotId id) const noexcept { return id.index(); }
};
