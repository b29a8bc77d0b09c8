#include "hydra_multi/net/hydra_robots.h"

#include <atomic>
#include <iomanip>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <zmq.hpp>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/net/clock.h"

namespace hydra_multi::net {
namespace {

/// A robot silent for longer than this is shown as silent, not connected.
constexpr double kSilentAfterS = 10.0;

std::string leftOutText(const std::map<std::string, size_t>& left_out) {
  std::string text;
  for (const auto& [what, n] : left_out)
    text += (text.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  return text;
}

}  // namespace

Result<HydraRobotSource> parseHydraRobotSource(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos)
    return Error{"'" + text + "' is not NAME=tcp://HOST:PORT (NAME a robot letter: a, b, ...)"};
  const std::string name = text.substr(0, eq);
  const std::optional<RobotId> robot = RobotId::parse(name);
  if (!robot)
    return Error{"'" + text + "': '" + name + "' is not a robot letter (a-z but p: a, b, ...)"};
  const std::string endpoint = text.substr(eq + 1);
  if (endpoint.rfind("tcp://", 0) != 0 || endpoint.size() <= 6 ||
      endpoint.find(':', 6) == std::string::npos)
    return Error{"'" + text + "': '" + endpoint + "' is not tcp://HOST:PORT"};
  return HydraRobotSource{*robot, endpoint};
}

struct HydraRobots::Impl {
  struct Link {
    HydraRobotSource source;
    HydraGraphInput input;
    zmq::socket_t sub;
    mutable std::mutex mutex;  // counts, heard, ended
    HydraRobotCounts counts;
    std::optional<Clock::time_point> heard;
    bool ended = false;  // told the station it is done
    std::thread thread;

    Link(HydraRobotSource s, HydraInputOptions o, zmq::context_t& context)
        : source(std::move(s)), input(source.robot, o), sub(context, zmq::socket_type::sub) {}
  };

  Station* station = nullptr;
  HydraRobotsOptions options;
  zmq::context_t context;
  std::vector<std::unique_ptr<Link>> links;
  std::atomic<bool> stopping{false};

  void log(const std::string& line) const {
    if (options.log) options.log(line);
  }
  std::string who(const Link& l) const {
    return "robot " + l.source.robot.str() + " (Hydra, " + l.source.endpoint + ")";
  }
  bool isDone(const Link& l) const {
    return options.done_after_s > 0.0 && l.heard && secondsSince(*l.heard) >= options.done_after_s;
  }
  void serve(Link& l);
  void take(Link& l, const zmq::message_t& message, size_t number);
  void status(const Link& l) const;
};

void HydraRobots::Impl::take(Link& l, const zmq::message_t& message, size_t number) {
  const std::string_view bytes(static_cast<const char*>(message.data()), message.size());
  const std::string at = who(l) + ": graph " + std::to_string(number) + " (" +
                         std::to_string(message.size()) + " bytes)";
  auto decoded = io::spark::decodeWire(bytes, options.version);
  if (!decoded) {
    {
      std::lock_guard<std::mutex> lock(l.mutex);
      ++l.counts.refused;
    }
    log("station: " + at + ": " + decoded.error() +
        "; left out (the next graph is taken against the last good one)");
    return;
  }
  HydraGraphNotes notes;
  auto taken = l.input.take(decoded.value(), &notes);
  if (!taken) {
    {
      std::lock_guard<std::mutex> lock(l.mutex);
      ++l.counts.refused;
    }
    log("station: " + at + ": " + taken.error() +
        "; left out (the next graph is taken against the last good one)");
    return;
  }
  if (number == 1 || !notes.correction.empty() || notes.bow_refused > 0) {
    if (notes.agent_prefix)
      log("station: " + who(l) + ": its agents carry the prefix '" +
          std::string(1, *notes.agent_prefix) + "', not '" + l.source.robot.str() +
          "'; taken as robot " + l.source.robot.str() + "'s keyframes");
    if (!notes.left_out.empty())
      log("station: " + at + ": left out " + leftOutText(notes.left_out));
    if (!notes.correction.empty())
      log("station: " + at + ": the robot corrected its map (" + notes.correction +
          "); taken whole");
    if (notes.bow_refused > 0)
      log("station: " + at + ": " + std::to_string(notes.bow_refused) +
          " agents' bags of words have dbow_ids and dbow_values that disagree; left out");
  }
  if (!taken.value()) {
    std::lock_guard<std::mutex> lock(l.mutex);
    l.counts.last_bytes = message.size();
    ++l.counts.unchanged;
    return;
  }
  RobotUpdate update = std::move(*taken.value());
  if (options.persist) {
    const Status stored =
        options.persist(update, io::encodeRobotUpdateBinary(update), message.size());
    if (!stored) {
      l.input.resumeAt(update.sequence);
      std::lock_guard<std::mutex> lock(l.mutex);
      ++l.counts.refused;
      log("station: " + at + ": not stored: " + stored.message() +
          "; the next graph is taken whole");
      return;
    }
  }
  const bool snapshot = update.is_snapshot;
  const uint64_t sequence = update.sequence;
  station->submit(std::move(update));
  std::lock_guard<std::mutex> lock(l.mutex);
  l.counts.last_bytes = message.size();
  ++l.counts.updates;
  if (snapshot) ++l.counts.snapshots;
  l.counts.next_sequence = sequence + 1;
}

void HydraRobots::Impl::status(const Link& l) const {
  std::lock_guard<std::mutex> lock(l.mutex);
  std::ostringstream line;
  line << std::fixed << std::setprecision(2) << "station: " << who(l) << ": ";
  if (!l.heard) {
    line << "no graph yet";
  } else if (isDone(l)) {
    line << "done (silent for " << static_cast<int>(secondsSince(*l.heard)) << " s)";
  } else if (secondsSince(*l.heard) < kSilentAfterS) {
    line << "connected";
  } else {
    line << "silent for " << static_cast<int>(secondsSince(*l.heard)) << " s";
  }
  line << ", " << l.counts.graphs << " graphs, " << l.counts.updates << " updates, "
       << double(l.counts.bytes) / 1e6 << " MB received";
  log(line.str());
}

void HydraRobots::Impl::serve(Link& l) {
  Clock::time_point last_status = Clock::now();
  while (!stopping) {
    if (options.status_s > 0.0 && secondsSince(last_status) >= options.status_s) {
      last_status = Clock::now();
      status(l);
    }
    bool tell_end = false;
    {
      std::lock_guard<std::mutex> lock(l.mutex);
      if (!l.ended && isDone(l)) tell_end = l.ended = true;
    }
    if (tell_end) {
      station->endOfStream(l.source.robot);
      log("station: " + who(l) + ": nothing for " + secondsText(options.done_after_s) +
          " s; taken as done");
    }
    zmq::pollitem_t item{l.sub.handle(), 0, ZMQ_POLLIN, 0};
    try {
      zmq::poll(&item, 1, std::chrono::milliseconds(100));
    } catch (const zmq::error_t&) {
      continue;  // interrupted by a signal: look at `stopping` again
    }
    if (!(item.revents & ZMQ_POLLIN)) continue;
    // The newest graph queued; the others are overtaken by it.
    zmq::message_t message, next;
    size_t received = 0, bytes = 0;
    while (l.sub.recv(next, zmq::recv_flags::dontwait)) {
      ++received;
      bytes += next.size();
      std::swap(message, next);
    }
    if (received == 0) continue;
    size_t number = 0;
    {
      std::lock_guard<std::mutex> lock(l.mutex);
      l.counts.graphs += received;
      l.counts.bytes += bytes;
      l.counts.overtaken += received - 1;
      number = l.counts.graphs;
      l.heard = Clock::now();
      if (l.ended) {
        l.ended = false;
        log("station: " + who(l) + ": sends again");
      }
    }
    take(l, message, number);
  }
}

Result<std::unique_ptr<HydraRobots>> HydraRobots::create(Station& station,
                                                         HydraRobotsOptions options) {
  if (const std::string bad = options.input.invalid(); !bad.empty())
    return Error{"Hydra robots: " + bad};
  auto impl = std::make_unique<Impl>();
  impl->station = &station;
  impl->options = std::move(options);
  std::set<RobotId> seen;
  for (const HydraRobotSource& s : impl->options.robots) {
    if (!seen.insert(s.robot).second)
      return Error{"--spark-robot: robot " + s.robot.str() + " is given twice"};
    auto link = std::make_unique<Impl::Link>(s, impl->options.input, impl->context);
    try {
      link->sub.set(zmq::sockopt::subscribe, "");
      link->sub.set(zmq::sockopt::linger, 0);
      link->sub.set(zmq::sockopt::maxmsgsize,
                    static_cast<int64_t>(impl->options.max_message_bytes));
      link->sub.connect(s.endpoint);
    } catch (const zmq::error_t& e) {
      return Error{"--spark-robot " + s.robot.str() + "=" + s.endpoint +
                   ": cannot connect: " + e.what()};
    }
    impl->links.push_back(std::move(link));
  }
  return std::unique_ptr<HydraRobots>(new HydraRobots(std::move(impl)));
}

HydraRobots::HydraRobots(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

HydraRobots::~HydraRobots() { stop(); }

void HydraRobots::resumeAt(RobotId robot, uint64_t next_sequence) {
  for (auto& l : impl_->links) {
    if (l->source.robot != robot) continue;
    l->input.resumeAt(next_sequence);
    l->counts.next_sequence = next_sequence;
  }
}

void HydraRobots::start() {
  for (auto& l : impl_->links) {
    if (l->thread.joinable()) continue;
    Impl::Link* link = l.get();
    Impl* impl = impl_.get();
    l->thread = std::thread([impl, link] { impl->serve(*link); });
  }
}

void HydraRobots::stop() {
  impl_->stopping = true;
  for (auto& l : impl_->links) {
    if (l->thread.joinable()) l->thread.join();
  }
}

bool HydraRobots::has(RobotId robot) const {
  for (const auto& l : impl_->links) {
    if (l->source.robot == robot) return true;
  }
  return false;
}

std::map<RobotId, RobotLinkState> HydraRobots::links() const {
  std::map<RobotId, RobotLinkState> out;
  for (const auto& l : impl_->links) {
    std::lock_guard<std::mutex> lock(l->mutex);
    RobotLinkState& s = out[l->source.robot];
    s.silent_s = l->heard ? secondsSince(*l->heard) : 0.0;
    s.connected = l->heard && s.silent_s < kSilentAfterS;
    s.said_bye = impl_->isDone(*l);
    s.bytes = l->counts.bytes;
  }
  return out;
}

size_t HydraRobots::done() const {
  size_t n = 0;
  for (const auto& l : impl_->links) {
    std::lock_guard<std::mutex> lock(l->mutex);
    n += impl_->isDone(*l) ? 1 : 0;
  }
  return n;
}

std::map<RobotId, HydraRobotCounts> HydraRobots::counts() const {
  std::map<RobotId, HydraRobotCounts> out;
  for (const auto& l : impl_->links) {
    std::lock_guard<std::mutex> lock(l->mutex);
    out[l->source.robot] = l->counts;
  }
  return out;
}

}  // namespace hydra_multi::net
