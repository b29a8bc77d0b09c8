#pragma once
// The command line's contract, in one place for every command (README "Errors and exit codes"):
//   - numbers are checked as they are parsed: finite, in the option's range, no sign on an
//     unsigned value, no overflow; the error names the option;
//   - paths are checked after parsing, before a command runs: an input file must be a file, an
//     input folder a folder, an output path not empty;
//   - every error goes to stderr as "hydra-multi: error: <what>", exit code kUsageError (2) for
//     a wrong command line and 1 for anything else (a missing or unusable file, a failed run).
// Only main.cpp sees CLI11; the commands get plain option structs (commands.h).

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hydra_multi/core/result.h"

namespace hydra_multi::apps {

/// Exit code of a command line that is wrong in itself (an unknown command or option, a missing
/// or bad value). Everything else that fails exits with 1.
inline constexpr int kUsageError = 2;

/// A closed range of real numbers, either end optionally open ("(0, 1]").
struct RealRange {
  double min = -std::numeric_limits<double>::max();
  double max = std::numeric_limits<double>::max();
  bool min_open = false, max_open = false;
};

/// Checks the text of a real number: a whole finite number within `range`. Empty when it is;
/// otherwise what is wrong ("'nan' is not a finite number").
std::string checkReal(const std::string& text, const RealRange& range);
/// Checks the text of an integer within [min, max]: digits only (a leading '-' only where min is
/// below 0), no overflow.
std::string checkInteger(const std::string& text, long double min, long double max);

/// "A" or "A-B" with A <= B, each an unsigned 64-bit seed, at most max_count seeds.
Result<std::pair<uint64_t, uint64_t>> parseSeedRange(const std::string& text, uint64_t max_count);

class CommandLine {
 public:
  explicit CommandLine(CLI::App& app) : app_(app) {}

  /// A real-number option checked against `range` (described in --help).
  CLI::Option* real(CLI::App* cmd, const std::string& name, double& value,
                    const std::string& description, const RealRange& range);
  /// The same for an optional value (absent unless given).
  CLI::Option* real(CLI::App* cmd, const std::string& name, std::optional<double>& value,
                    const std::string& description, const RealRange& range);

  /// An integer option within [min, max] (inclusive; described in --help).
  template <typename T>
  CLI::Option* integer(CLI::App* cmd, const std::string& name, T& value,
                       const std::string& description, T min, T max) {
    return cmd->add_option(name, value, description)->check(integerValidator(min, max));
  }
  template <typename T>
  CLI::Option* integer(CLI::App* cmd, const std::string& name, std::optional<T>& value,
                       const std::string& description, T min, T max) {
    return cmd->add_option(name, value, description)->check(integerValidator(min, max));
  }

  /// Path options, checked after parsing, before the command runs (exit 1 naming the path): input
  /// files and folders must exist and be of their kind. No path may be empty (a usage error).
  CLI::Option* inputFile(CLI::App* cmd, const std::string& name, std::string& path,
                         const std::string& description);
  CLI::Option* inputFiles(CLI::App* cmd, const std::string& name, std::vector<std::string>& paths,
                          const std::string& description);
  CLI::Option* inputDirectory(CLI::App* cmd, const std::string& name, std::string& path,
                              const std::string& description);
  /// Output paths: a file must not be a folder and its folder must exist; a folder (created
  /// when missing) must not be a file.
  CLI::Option* outputFile(CLI::App* cmd, const std::string& name, std::string& path,
                          const std::string& description);
  CLI::Option* outputDirectory(CLI::App* cmd, const std::string& name, std::string& path,
                               const std::string& description);

  /// Parses the command line. Returns the exit code when the program should end now (help,
  /// version, any error, printed), or -1 when the chosen command should run.
  int parse(int argc, char** argv);
  /// A wrong command line found after parsing: printed as parse() prints one; returns
  /// kUsageError.
  int refuse(const std::string& command, const std::string& what) const;

 private:
  template <typename T>
  static CLI::Validator integerValidator(T min, T max) {
    const auto lo = static_cast<long double>(min), hi = static_cast<long double>(max);
    return CLI::Validator([lo, hi](std::string& text) { return checkInteger(text, lo, hi); },
                          rangeText(lo, hi), "integer");
  }
  static std::string rangeText(long double min, long double max);
  static CLI::Validator realValidator(const RealRange& range);

  enum class PathKind { kInputFile, kInputDirectory, kOutputFile, kOutputDirectory };
  struct PathCheck {
    CLI::App* command = nullptr;
    std::string option;
    std::function<std::vector<std::string>()> paths;
    PathKind kind = PathKind::kInputFile;
  };
  CLI::Option* pathOption(CLI::App* cmd, const std::string& name, std::string& path,
                          const std::string& description, PathKind kind);
  static Status checkPath(const std::string& path, PathKind kind);
  /// The first path of the command that ran which is not what its option needs, as an error.
  Status checkPaths() const;

  CLI::App& app_;
  std::vector<PathCheck> path_checks_;
};

}  // namespace hydra_multi::apps
