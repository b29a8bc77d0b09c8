#include "hydra_multi/net/payload.h"

#include <zstd.h>

namespace hydra_multi::net {

bool isCompressed(std::string_view payload) {
  return payload.size() >= 4 && static_cast<uint8_t>(payload[0]) == 0x28 &&
         static_cast<uint8_t>(payload[1]) == 0xB5 && static_cast<uint8_t>(payload[2]) == 0x2F &&
         static_cast<uint8_t>(payload[3]) == 0xFD;
}

std::string compressPayload(std::string_view record, int level) {
  std::string out(ZSTD_compressBound(record.size()), '\0');
  const size_t n = ZSTD_compress(out.data(), out.size(), record.data(), record.size(), level);
  if (ZSTD_isError(n)) return std::string(record);  // cannot happen with a bound-sized buffer
  out.resize(n);
  return out;
}

Result<std::string> expandPayload(std::string_view payload, size_t limit) {
  if (!isCompressed(payload)) return std::string(payload);
  const size_t frame = ZSTD_findFrameCompressedSize(payload.data(), payload.size());
  if (ZSTD_isError(frame)) return Error{std::string("zstd frame: ") + ZSTD_getErrorName(frame)};
  if (frame != payload.size())
    return Error{"zstd frame of " + std::to_string(frame) + " bytes followed by " +
                 std::to_string(payload.size() - frame) + " more"};
  const unsigned long long size = ZSTD_getFrameContentSize(payload.data(), payload.size());
  if (size == ZSTD_CONTENTSIZE_UNKNOWN) return Error{"zstd frame without its content size"};
  if (size == ZSTD_CONTENTSIZE_ERROR) return Error{"zstd frame: not a valid frame header"};
  if (size > limit)
    return Error{"zstd frame expands to " + std::to_string(size) +
                 " bytes, more than the limit of " + std::to_string(limit)};
  std::string out(static_cast<size_t>(size), '\0');
  const size_t n = ZSTD_decompress(out.data(), out.size(), payload.data(), payload.size());
  if (ZSTD_isError(n)) return Error{std::string("zstd frame: ") + ZSTD_getErrorName(n)};
  if (n != out.size())
    return Error{"zstd frame expands to " + std::to_string(n) + " bytes, not the " +
                 std::to_string(size) + " it says"};
  return out;
}

}  // namespace hydra_multi::net
