#pragma once
// SIGINT and SIGTERM as a request to stop, for the commands that run until told (station, watch):
// while a StopSignals lives, either signal sets a flag the command's loop asks; when it goes, the
// default handlers are back. One at a time.

namespace hydra_multi::apps {

class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  /// Whether SIGINT or SIGTERM came since this was made.
  static bool requested();
};

}  // namespace hydra_multi::apps
