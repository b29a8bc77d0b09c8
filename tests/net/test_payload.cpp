// An UPDATE's payload: a record as it is, or a zstd frame of it, expanded only when the frame says
// a size within the limit; whatever else is refused with what is wrong.

#include <gtest/gtest.h>
#include <zstd.h>

#include "hydra_multi/net/payload.h"

namespace hydra_multi::net {
namespace {

const std::string kRecord = "HMDG" + std::string(5000, 'r') + "tail";

TEST(Payload, RecordsPassAndFramesExpand) {
  EXPECT_FALSE(isCompressed(kRecord));
  EXPECT_EQ(expandPayload(kRecord, 10).value(), kRecord);  // a record is not expanded: no limit
  const std::string packed = compressPayload(kRecord);
  EXPECT_TRUE(isCompressed(packed));
  EXPECT_LT(packed.size(), kRecord.size() / 10);
  EXPECT_EQ(expandPayload(packed, kRecord.size()).value(), kRecord);
}

TEST(Payload, RefusesFramesThatDoNotFit) {
  const std::string packed = compressPayload(kRecord);
  EXPECT_EQ(expandPayload(packed, kRecord.size() - 1).error(),
            "zstd frame expands to 5008 bytes, more than the limit of 5007");
  EXPECT_EQ(expandPayload(packed + "xy", 1 << 20).error(),
            "zstd frame of " + std::to_string(packed.size()) + " bytes followed by 2 more");
  std::string damaged = packed;
  damaged.resize(damaged.size() - 3);
  EXPECT_EQ(expandPayload(damaged, 1 << 20).error().rfind("zstd frame: ", 0), 0u);
  // A frame that does not say its size (a streaming compressor's) is not expanded.
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 0);
  std::string unsized(ZSTD_compressBound(kRecord.size()), '\0');
  unsized.resize(
      ZSTD_compress2(cctx, unsized.data(), unsized.size(), kRecord.data(), kRecord.size()));
  ZSTD_freeCCtx(cctx);
  EXPECT_EQ(expandPayload(unsized, 1 << 20).error(), "zstd frame without its content size");
}

}  // namespace
}  // namespace hydra_multi::net
