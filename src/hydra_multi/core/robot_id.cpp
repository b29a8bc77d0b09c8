#include "hydra_multi/core/robot_id.h"

namespace hydra_multi {

std::optional<RobotId> RobotId::fromPrefix(char letter) {
  if (letter < 'a' || letter > 'z' || letter == 'p') return std::nullopt;
  const int index = letter < 'p' ? letter - 'a' : letter - 'a' - 1;
  return RobotId(static_cast<uint8_t>(index));
}

std::optional<RobotId> RobotId::parse(const std::string& name) {
  if (name.size() != 1) return std::nullopt;
  return fromPrefix(name[0]);
}

char RobotId::prefix() const {
  if (!isValid()) return '?';
  return static_cast<char>(index_ < 15 ? 'a' + index_ : 'a' + index_ + 1);
}

}  // namespace hydra_multi
