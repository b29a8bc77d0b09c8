#pragma once
// The time helpers of the network units: their steady clock, seconds since a moment, a duration
// of seconds, and seconds as log text ("0.3", "16").

#include <chrono>
#include <sstream>
#include <string>

namespace hydra_multi::net {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

inline Clock::duration secondsDuration(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

inline std::string secondsText(double s) {
  std::ostringstream text;
  text << s;
  return text.str();
}

}  // namespace hydra_multi::net
