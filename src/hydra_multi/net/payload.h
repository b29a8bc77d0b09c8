#pragma once
// An UPDATE's payload on the wire (docs/PROTOCOL.md): the robot-update record as it is, or one
// zstd frame of it when the station's WELCOME offers zstd. The two are told apart by their first
// bytes (a record's magic "HMDG", zstd's 28 B5 2F FD). A zstd frame must say the size it expands
// to, and that size must be within the caller's limit, before anything is expanded.

#include <string>
#include <string_view>

#include "hydra_multi/core/result.h"

namespace hydra_multi::net {

/// The record as one zstd frame (level 3: docs/DECISIONS.md).
std::string compressPayload(std::string_view record, int level = 3);
/// The record a payload carries: itself, or the expansion of its zstd frame. Refused: a frame
/// that does not say its size, says more than `limit`, is damaged, or is followed by more bytes.
Result<std::string> expandPayload(std::string_view payload, size_t limit);
/// Whether a payload is a zstd frame.
bool isCompressed(std::string_view payload);

}  // namespace hydra_multi::net
