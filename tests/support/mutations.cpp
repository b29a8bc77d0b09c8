#include "support/mutations.h"

namespace hydra_multi::testing {

std::string mutateBytes(std::string s, std::mt19937& rng) {
  auto pick = [&](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  const int kind = static_cast<int>(rng() % 7);
  const int repeats = 1 + static_cast<int>(rng() % 4);
  for (int r = 0; r < repeats; ++r) {
    switch (kind) {
      case 0:
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(rng());
        break;
      case 2:
        s.resize(pick(s.size() + 1));
        break;
      case 3:
        s.insert(pick(s.size() + 1), std::string(1 + pick(8), static_cast<char>(rng())));
        break;
      case 4:
        if (!s.empty()) s.erase(pick(s.size()), 1 + pick(16));
        break;
      case 5:
        if (!s.empty()) {
          const size_t at = pick(s.size());
          s.insert(pick(s.size() + 1), s.substr(at, 1 + pick(32)));
        }
        break;
      default: {
        std::string noise(pick(64), '\0');
        for (char& c : noise) c = static_cast<char>(rng());
        return noise;
      }
    }
  }
  return s;
}

}  // namespace hydra_multi::testing
