#include "hydra_multi/apps/command_line.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace hydra_multi::apps {
namespace {

std::string number(long double value) {
  std::ostringstream s;
  s.precision(20);
  s << value;
  return s.str();
}

std::string realText(double value) {
  if (value == std::numeric_limits<double>::max()) return "inf";
  if (value == -std::numeric_limits<double>::max()) return "-inf";
  std::ostringstream s;
  s << value;
  return s.str();
}

std::string describe(const RealRange& r) {
  const bool unbounded = r.max == std::numeric_limits<double>::max();
  return std::string(r.min_open ? "(" : "[") + realText(r.min) + ", " + realText(r.max) +
         (r.max_open || unbounded ? ")" : "]");
}

// The whole text as an unsigned integer, or nothing (not digits, or too large).
std::optional<uint64_t> parseUnsigned(const std::string& text, bool* overflow) {
  uint64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  *overflow = ec == std::errc::result_out_of_range;
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

}  // namespace

std::string checkReal(const std::string& text, const RealRange& range) {
  const std::string expected = " (expected a number in " + describe(range) + ")";
  if (text.empty()) return "an empty value is not a number" + expected;
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0') return "'" + text + "' is not a number" + expected;
  if (!std::isfinite(value) || errno == ERANGE)
    return "'" + text + "' is not a finite, representable number" + expected;
  const bool below = range.min_open ? value <= range.min : value < range.min;
  const bool above = range.max_open ? value >= range.max : value > range.max;
  if (below || above) return text + " is outside " + describe(range);
  return "";
}

std::string checkInteger(const std::string& text, long double min, long double max) {
  const std::string range = "[" + number(min) + ", " + number(max) + "]";
  const std::string expected = " (expected an integer in " + range + ")";
  if (text.empty()) return "an empty value is not an integer" + expected;
  const bool negative = text[0] == '-';
  bool overflow = false;
  const auto magnitude = parseUnsigned(negative ? text.substr(1) : text, &overflow);
  if (overflow) return text + " is too large" + expected;
  if (!magnitude) return "'" + text + "' is not an integer" + expected;
  const long double value =
      negative ? -static_cast<long double>(*magnitude) : static_cast<long double>(*magnitude);
  if (value < min || value > max) return text + " is outside " + range;
  return "";
}

Result<std::pair<uint64_t, uint64_t>> parseSeedRange(const std::string& text, uint64_t max_count) {
  const std::string expected =
      "expected A-B or one seed A (unsigned integers, A <= B), got '" + text + "'";
  const size_t dash = text.find('-');
  bool overflow = false;
  const auto first = parseUnsigned(text.substr(0, dash), &overflow);
  if (overflow) return Error{text.substr(0, dash) + " is too large for a seed; " + expected};
  if (!first) return Error{expected};
  uint64_t last = *first;
  if (dash != std::string::npos) {
    const auto second = parseUnsigned(text.substr(dash + 1), &overflow);
    if (overflow) return Error{text.substr(dash + 1) + " is too large for a seed; " + expected};
    if (!second) return Error{expected};
    last = *second;
  }
  if (last < *first) return Error{"the last seed is below the first in '" + text + "'"};
  if (last - *first >= max_count)
    return Error{"'" + text + "' is more than " + std::to_string(max_count) +
                 " seeds; run them in several calls"};
  return std::make_pair(*first, last);
}

std::string CommandLine::rangeText(long double min, long double max) {
  return "in [" + number(min) + ", " + number(max) + "]";
}

CLI::Validator CommandLine::realValidator(const RealRange& range) {
  return CLI::Validator([range](std::string& text) { return checkReal(text, range); },
                        "in " + describe(range), "real");
}

CLI::Option* CommandLine::real(CLI::App* cmd, const std::string& name, double& value,
                               const std::string& description, const RealRange& range) {
  return cmd->add_option(name, value, description)->check(realValidator(range));
}

CLI::Option* CommandLine::real(CLI::App* cmd, const std::string& name, std::optional<double>& value,
                               const std::string& description, const RealRange& range) {
  return cmd->add_option(name, value, description)->check(realValidator(range));
}

namespace {

CLI::Validator nonEmptyPath() {
  return CLI::Validator(
      [](std::string& text) { return text.empty() ? std::string("the path is empty") : ""; }, "",
      "path");
}

}  // namespace

CLI::Option* CommandLine::pathOption(CLI::App* cmd, const std::string& name, std::string& path,
                                     const std::string& description, PathKind kind) {
  CLI::Option* option = cmd->add_option(name, path, description)->check(nonEmptyPath());
  path_checks_.push_back({cmd, name, [&path] { return std::vector<std::string>{path}; }, kind});
  return option;
}

CLI::Option* CommandLine::inputFile(CLI::App* cmd, const std::string& name, std::string& path,
                                    const std::string& description) {
  return pathOption(cmd, name, path, description, PathKind::kInputFile);
}

CLI::Option* CommandLine::inputFiles(CLI::App* cmd, const std::string& name,
                                     std::vector<std::string>& paths,
                                     const std::string& description) {
  CLI::Option* option = cmd->add_option(name, paths, description)->check(nonEmptyPath());
  path_checks_.push_back({cmd, name, [&paths] { return paths; }, PathKind::kInputFile});
  return option;
}

CLI::Option* CommandLine::inputDirectory(CLI::App* cmd, const std::string& name, std::string& path,
                                         const std::string& description) {
  return pathOption(cmd, name, path, description, PathKind::kInputDirectory);
}

CLI::Option* CommandLine::outputFile(CLI::App* cmd, const std::string& name, std::string& path,
                                     const std::string& description) {
  return pathOption(cmd, name, path, description, PathKind::kOutputFile);
}

CLI::Option* CommandLine::outputDirectory(CLI::App* cmd, const std::string& name, std::string& path,
                                          const std::string& description) {
  return pathOption(cmd, name, path, description, PathKind::kOutputDirectory);
}

Status CommandLine::checkPath(const std::string& path, PathKind kind) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  const bool exists = fs::exists(status), folder = fs::is_directory(status);
  switch (kind) {
    case PathKind::kInputFile:
      if (!exists) return Error{path + ": no such file"};
      if (folder) return Error{path + ": is a folder, not a file"};
      break;
    case PathKind::kInputDirectory:
      if (!exists) return Error{path + ": no such folder"};
      if (!folder) return Error{path + ": not a folder"};
      break;
    case PathKind::kOutputFile: {
      if (folder) return Error{path + ": is a folder; give a file name"};
      const fs::path parent = fs::path(path).parent_path();
      if (!parent.empty() && !fs::is_directory(parent, ec))
        return Error{path + ": no folder " + parent.string() + " to write it in"};
      break;
    }
    case PathKind::kOutputDirectory:
      if (exists && !folder) return Error{path + ": is a file, not a folder"};
      break;
  }
  return Status::Ok();
}

Status CommandLine::checkPaths() const {
  for (const PathCheck& check : path_checks_) {
    if (!check.command->parsed()) continue;
    for (const std::string& path : check.paths()) {
      if (path.empty()) continue;  // not given (optional)
      if (Status s = checkPath(path, check.kind); !s)
        return Error{s.message() + " (" + check.command->get_name() + " " + check.option + ")"};
    }
  }
  return Status::Ok();
}

int CommandLine::refuse(const std::string& command, const std::string& what) const {
  std::cerr << "hydra-multi: error: " << (command.empty() ? "" : command + ": ") << what
            << "; see hydra-multi " << (command.empty() ? "" : command + " ") << "--help\n";
  return kUsageError;
}

int CommandLine::parse(int argc, char** argv) {
  const std::string program = "hydra-multi: error: ";
  const CLI::App& app = app_;
  std::string commands;
  bool known = false;
  const std::string first = argc > 1 ? argv[1] : "";
  for (const CLI::App* sub : app.get_subcommands(std::function<bool(const CLI::App*)>())) {
    commands += (commands.empty() ? "" : ", ") + sub->get_name();
    known = known || sub->get_name() == first;
  }
  // The command comes first; anything else there is named as what it is.
  if (argc < 2) {
    std::cerr << program << "give a command (" << commands << "); see hydra-multi --help\n";
    return kUsageError;
  }
  if (!first.empty() && first[0] != '-' && !known) {
    std::cerr << program << "unknown command '" << first << "' (commands: " << commands
              << "); see hydra-multi --help\n";
    return kUsageError;
  }
  // Arguments no option takes are collected (not thrown at once), so that they are named first:
  // "unknown option --x" says more than the "--dataset is required" that CLI11 would give.
  app_.allow_extras();
  for (CLI::App* sub : app_.get_subcommands(std::function<bool(CLI::App*)>())) sub->allow_extras();
  std::string error;
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app_.exit(e);
    error = e.what();
  }
  std::string command;
  std::vector<std::string> extras = app_.remaining();
  for (const CLI::App* sub : app_.get_subcommands()) {
    command = sub->get_name();
    for (const std::string& extra : sub->remaining()) extras.push_back(extra);
  }
  if (!extras.empty()) {
    const std::string& extra = extras.front();
    error = (extra.size() > 1 && extra[0] == '-' ? "unknown option " : "unexpected argument ") +
            std::string("'") + extra + "'";
  }
  if (!error.empty()) return refuse(command, error);
  if (Status s = checkPaths(); !s) {
    std::cerr << program << s.message() << "\n";
    return 1;
  }
  return -1;
}

}  // namespace hydra_multi::apps
