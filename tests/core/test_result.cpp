#include <gtest/gtest.h>

#include "hydra_multi/core/result.h"

namespace hydra_multi {
namespace {

// A Result holds either its value or its message, never both; reading a missing value throws.
TEST(Result, HoldsValueOrError) {
  Result<int> good = 5;
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(good.value(), 5);
  EXPECT_TRUE(good.error().empty());

  Result<int> bad = Error{"file.json: line 3: bad"};
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "file.json: line 3: bad");
  EXPECT_THROW((void)bad.value(), std::logic_error);
  EXPECT_FALSE(bad.status().ok());
  EXPECT_EQ(bad.status().message(), "file.json: line 3: bad");

  // A string value is not mistaken for an error.
  Result<std::string> text = std::string("hello");
  EXPECT_TRUE(text.ok());
}

TEST(Status, OkOrMessage) {
  EXPECT_TRUE(Status::Ok().ok());
  const Status status = Error{"broken"};
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.message(), "broken");
}

}  // namespace
}  // namespace hydra_multi
