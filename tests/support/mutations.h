#pragma once
// Seeded byte-level mutations of valid inputs, for the decoders' fuzz tests.

#include <random>
#include <string>

namespace hydra_multi::testing {

/// One to four mutations of one kind: bit flips, overwrites, truncation, insertion, deletion,
/// duplication of a piece, or random noise in place of the whole input.
std::string mutateBytes(std::string s, std::mt19937& rng);

}  // namespace hydra_multi::testing
