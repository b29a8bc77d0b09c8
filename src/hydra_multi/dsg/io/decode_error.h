#pragma once
// DecodeError: how the decoders unwind on bad input. It never leaves the io module: every public
// decoder catches it and returns an Error whose message says what was wrong and where (the item,
// and the byte offset or JSON path).

#include <stdexcept>
#include <string>

namespace hydra_multi::io {

class DecodeError : public std::runtime_error {
 public:
  explicit DecodeError(const std::string& message) : std::runtime_error(message) {}
  /// The same error with "context: " in front, e.g. "node 12: " + "byte 80: truncated".
  DecodeError within(const std::string& context) const {
    return DecodeError(context + ": " + what());
  }
};

}  // namespace hydra_multi::io
