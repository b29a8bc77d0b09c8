// Look-ups for ascending keys find what std::map::find finds, walking the map once.

#include <gtest/gtest.h>

#include <map>

#include "hydra_multi/core/ascending_lookup.h"

namespace hydra_multi {
namespace {

TEST(AscendingLookup, FindsWhatFindFindsForAscendingKeys) {
  std::map<int, double> map;
  for (int k = 0; k < 100; k += 3) map[k] = 0.5 * k;
  AscendingLookup lookup(map);
  for (int key = -2; key < 105; key += (key % 7 == 0 ? 4 : 1)) {  // some keys skipped
    const double* found = lookup.find(key);
    const auto it = map.find(key);
    ASSERT_EQ(found != nullptr, it != map.end()) << key;
    if (found != nullptr) {
      EXPECT_EQ(found, &it->second) << key;
    }
  }
  // Asked again, the last key is still found; nothing is found in an empty map.
  AscendingLookup again(map);
  EXPECT_NE(again.find(99), nullptr);
  EXPECT_NE(again.find(99), nullptr);
  EXPECT_EQ(again.find(100), nullptr);
  const std::map<int, double> empty;
  EXPECT_EQ(AscendingLookup(empty).find(0), nullptr);
}

}  // namespace
}  // namespace hydra_multi
