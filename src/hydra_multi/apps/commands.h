#pragma once
// The subcommands of `hydra-multi`. Each takes a plain options struct that main() fills from the
// command line, prints to stdout (results) and stderr (errors, progress), and returns the exit
// code: 0 success, 1 failure.

#include <string>

namespace hydra_multi::apps {

struct InfoOptions {
  std::string path;
  bool json = false;  ///< exactly one JSON object on stdout
};
int runInfo(const InfoOptions& options);

struct ConvertOptions {
  std::string input;
  std::string output;
};
int runConvert(const ConvertOptions& options);

/// Prints "hydra-multi: error: <message>" on stderr and returns 1.
int fail(const std::string& message);

}  // namespace hydra_multi::apps
