#pragma once
// What every fuzz target asserts besides "no crash, no sanitizer report": a refusal says what was
// wrong, and what decodes survives its own round trip. A failed check aborts, so libFuzzer keeps
// the input as a crash.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "hydra_multi/core/result.h"

namespace hydra_multi::fuzz {

[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "fuzz check failed: %s\n", what);
  std::abort();
}

/// A Result: when it failed, its message must say something.
template <typename R>
bool decoded(const R& result) {
  if (result.ok()) return true;
  if (result.error().empty()) fail("an error without a message");
  return false;
}

/// A Status: when it failed, its message must say something.
inline bool succeeded(const Status& status) {
  if (status.ok()) return true;
  if (status.message().empty()) fail("an error without a message");
  return false;
}

}  // namespace hydra_multi::fuzz
