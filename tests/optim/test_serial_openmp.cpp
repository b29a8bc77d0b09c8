#include <gtest/gtest.h>
#include <omp.h>

#include <thread>

#include "hydra_multi/optim/serial_openmp.h"

namespace hydra_multi {
namespace {

int teamOfFour() {
  int team = 0;
#pragma omp parallel num_threads(4)
  {
#pragma omp single
    team = omp_get_num_threads();
  }
  return team;
}

int regionLevel() {  // nested regions in the one a parallel directive opens: 1 in a team
  int level = -1;
#pragma omp parallel num_threads(4)
  {
#pragma omp single
    level = omp_get_level();
  }
  return level;
}

TEST(SerialOpenMp, RegionsRunOnTheCallingThreadWhileItLives) {
  omp_set_max_active_levels(2);
  ASSERT_EQ(teamOfFour(), 4);
  {
    const SerialOpenMp serial;
    EXPECT_EQ(teamOfFour(), 1);
    {
      const SerialOpenMp nested;
      EXPECT_EQ(teamOfFour(), 1);
    }
    EXPECT_EQ(teamOfFour(), 1);  // the inner one restored the outer one's setting
  }
  EXPECT_EQ(omp_get_max_active_levels(), 2);
  EXPECT_EQ(teamOfFour(), 4);
}

TEST(SerialOpenMp, OnlyTheThreadThatHoldsIt) {
  const SerialOpenMp serial;
  int other = 0;
  std::thread([&other] { other = teamOfFour(); }).join();
  EXPECT_EQ(other, 4);
  EXPECT_EQ(teamOfFour(), 1);
}

TEST(SerialOpenMp, RegionsOpenNoTeamWhileItLives) {
  EXPECT_EQ(regionLevel(), 1);  // libgomp's team
  {
    const SerialOpenMp serial;
    EXPECT_EQ(regionLevel(), 0);  // the region's function called directly, as CHOLMOD's loops are
  }
  EXPECT_EQ(regionLevel(), 1);
}

}  // namespace
}  // namespace hydra_multi
