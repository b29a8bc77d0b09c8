#include "hydra_multi/net/robot_client.h"

#include <map>
#include <optional>
#include <thread>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/net/clock.h"
#include "hydra_multi/net/interruptible_poll.h"
#include "hydra_multi/net/keys.h"
#include "hydra_multi/net/payload.h"
#include "hydra_multi/net/protocol.h"

namespace hydra_multi::net {
namespace {

struct Entry {
  std::string payload;  // the update as one .dsgb record
  std::string packed;   // the same, zstd-compressed (made when first sent to a station taking it)
  bool in_flight = false;
  bool ever_sent = false;
  bool snapshot = false;  // acknowledged only by the cumulative ACK passing it (see kAck)
  Clock::time_point sent_at;
};

Entry entryOf(std::string payload) {
  Entry entry;
  entry.payload = std::move(payload);
  return entry;
}

}  // namespace

struct RobotClient::Impl {
  enum class State { kDisconnected, kHelloSent, kWelcomed };

  Impl(RobotId r, uint32_t layers, RobotClientOptions o)
      : robot(r), provided_layers(layers), options(std::move(o)) {
    if (options.epoch == 0)
      options.epoch =
          static_cast<uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
    backoff_s = options.backoff_min_s;
  }

  void log(const std::string& line) const {
    if (options.log) options.log("robot " + robot.str() + ": " + line);
  }
  bool send(const Message& m);
  void connect();
  void disconnect(const std::string& why);
  void receive();
  void handle(const Message& m);
  void sendUpdates();
  void answerSnapshotRequest(const Message& m);
  // Adds an update to the robot's map (what a snapshot is built from).
  void addToMap(const RobotUpdate& update);

  RobotId robot;
  uint32_t provided_layers;
  RobotClientOptions options;
  zmq::context_t context;
  std::optional<zmq::socket_t> socket;
  State state = State::kDisconnected;
  Clock::time_point reconnect_at = Clock::now(), last_heard = Clock::now(),
                    last_sent = Clock::now();
  double backoff_s = 0.5;
  std::map<uint64_t, Entry> outbox;  // by sequence
  uint64_t held_before = 0;          // the station's cumulative ACK: it holds every update before
  size_t in_flight = 0;
  std::string fatal;
  bool bye_answered = false;
  bool zstd = false;       // the station's WELCOME offers it
  RobotStreamState map;    // every update enqueued or folded, as one snapshot
  std::string map_broken;  // why `map` is not the robot's map (an update did not add); empty: it is
  RobotClientCounts counts;
};

void RobotClient::Impl::addToMap(const RobotUpdate& update) {
  if (!map_broken.empty() && !update.is_snapshot) return;
  if (Status added = map.add(update); !added) {
    map_broken = added.message();
    log("no snapshot can be sent until the next one in the stream: " + map_broken);
  } else {
    map_broken.clear();
  }
}

void RobotClient::Impl::answerSnapshotRequest(const Message& m) {
  if (map.updatesAdded() == 0 || !map_broken.empty()) {
    log("the station asked for a snapshot; there is none to send" +
        (map_broken.empty() ? std::string(" (no update yet)") : ": " + map_broken));
    return;
  }
  RobotUpdate snapshot = map.snapshot();
  if (snapshot.sequence < m.next_sequence) {
    log("the station asked for a snapshot, and holds everything (before " +
        std::to_string(m.next_sequence) + ") already");
    return;
  }
  // The snapshot stands for every update up to its sequence: it replaces them in the outbox.
  for (auto it = outbox.begin(); it != outbox.end() && it->first <= snapshot.sequence;) {
    if (it->second.in_flight) --in_flight;
    it = outbox.erase(it);
  }
  outbox[snapshot.sequence] = entryOf(io::encodeRobotUpdateBinary(snapshot));
  outbox[snapshot.sequence].snapshot = true;
  ++counts.snapshots;
  log("the station asked for a snapshot: sending one of every update up to " +
      std::to_string(snapshot.sequence) + " (" +
      std::to_string(outbox[snapshot.sequence].payload.size()) + " bytes)");
}

bool RobotClient::Impl::send(const Message& m) {
  if (!socket) return false;
  std::vector<zmq::message_t> parts;
  for (const std::string& frame : encodeMessage(m)) {
    counts.bytes += frame.size();
    parts.emplace_back(frame.data(), frame.size());
  }
  const bool sent = zmq::send_multipart(*socket, parts, zmq::send_flags::dontwait).has_value();
  if (sent) last_sent = Clock::now();
  return sent;
}

void RobotClient::Impl::connect() {
  socket.emplace(context, zmq::socket_type::dealer);
  socket->set(zmq::sockopt::linger, 0);
  try {
    if (!options.secret_key.empty()) {
      auto own = publicKeyOf(options.secret_key);
      if (!own) {
        fatal = "its key: " + own.error();
        socket.reset();
        return;
      }
      socket->set(zmq::sockopt::curve_secretkey, options.secret_key);
      socket->set(zmq::sockopt::curve_publickey, own.value());
      socket->set(zmq::sockopt::curve_serverkey, options.station_key);
    }
    socket->connect(options.connect);
  } catch (const zmq::error_t& e) {
    fatal = options.connect + ": cannot connect: " + e.what();
    socket.reset();
    return;
  }
  state = State::kHelloSent;
  last_heard = Clock::now();
  send(hello(robot, options.epoch, provided_layers));
}

void RobotClient::Impl::disconnect(const std::string& why) {
  log(why + "; connecting again in " + secondsText(backoff_s) + " s");
  socket.reset();
  state = State::kDisconnected;
  reconnect_at = Clock::now() + secondsDuration(backoff_s);
  backoff_s = std::min(2.0 * backoff_s, options.backoff_max_s);
  for (auto& [sequence, entry] : outbox) entry.in_flight = false;
  in_flight = 0;
}

void RobotClient::Impl::handle(const Message& m) {
  last_heard = Clock::now();
  switch (m.type) {
    case MessageType::kWelcome: {
      // The station holds everything before next_sequence: drop it, send the rest again.
      ++counts.connections;
      state = State::kWelcomed;
      zstd = m.zstd && options.compress;
      backoff_s = options.backoff_min_s;
      if (m.next_sequence < held_before) {
        counts.lost_acknowledged += held_before - m.next_sequence;
        log("the station lost updates it had acknowledged: it holds every update before " +
            std::to_string(m.next_sequence) + ", it had acknowledged every update before " +
            std::to_string(held_before));
      }
      held_before = m.next_sequence;
      // Those the station holds count as acknowledged (their ACK was lost with a connection).
      const auto held = outbox.lower_bound(m.next_sequence);
      counts.acknowledged += static_cast<size_t>(std::distance(outbox.begin(), held));
      outbox.erase(outbox.begin(), held);
      for (auto& [sequence, entry] : outbox) entry.in_flight = false;
      in_flight = 0;
      log("welcomed, the station holds every update before " + std::to_string(m.next_sequence) +
          ", " + std::to_string(outbox.size()) + " to send");
      return;
    }
    case MessageType::kAck: {
      const auto acknowledge = [this](std::map<uint64_t, Entry>::iterator it) {
        if (it->second.in_flight) --in_flight;
        ++counts.acknowledged;
        return outbox.erase(it);
      };
      held_before = std::max(held_before, m.next_sequence);
      // An ACK names a sequence, not whether it was a delta or a snapshot: a snapshot that took
      // the sequence of a delta still in flight is acknowledged only once the station holds
      // everything up to it.
      if (auto it = outbox.find(m.sequence); it != outbox.end() && !it->second.snapshot)
        acknowledge(it);
      for (auto it = outbox.begin(); it != outbox.end() && it->first < m.next_sequence;)
        it = acknowledge(it);
      return;
    }
    case MessageType::kRefuse: {
      if (m.code == RefuseCode::kNoHello) {
        if (state != State::kWelcomed) return;  // a HELLO is on its way already
        // The station does not know this connection: it restarted, and ZeroMQ reconnected the
        // socket underneath. Say HELLO again; its WELCOME says what it holds.
        log("the station does not know this connection (" + m.text + "); saying HELLO again");
        state = State::kHelloSent;
        for (auto& [sequence, entry] : outbox) entry.in_flight = false;
        in_flight = 0;
        bye_answered = false;
        send(hello(robot, options.epoch, provided_layers));
        return;
      }
      if (m.sequence == kNoSequence) {
        // A refused HELLO ends the mission; other refused messages are only logged.
        if (state == State::kHelloSent) {
          fatal = "the station refused: " + m.text;
          log(fatal);
        } else {
          log("the station refused a message: " + m.text);
        }
        return;
      }
      log("the station refused update " + std::to_string(m.sequence) + ": " + m.text);
      if (auto it = outbox.find(m.sequence); it != outbox.end()) {
        if (it->second.in_flight) --in_flight;
        outbox.erase(it);
        ++counts.refused;
      }
      return;
    }
    case MessageType::kBye:
      bye_answered = true;
      return;
    case MessageType::kSnapshotRequest:
      answerSnapshotRequest(m);
      return;
    default:
      return;  // heartbeats: being heard is all
  }
}

void RobotClient::Impl::receive() {
  if (!socket) return;
  for (int i = 0; i < 1000; ++i) {
    std::vector<zmq::message_t> parts;
    if (!zmq::recv_multipart(*socket, std::back_inserter(parts), zmq::recv_flags::dontwait)) return;
    std::vector<std::string> frames;
    for (zmq::message_t& part : parts) frames.push_back(part.to_string());
    auto m = decodeMessage(frames);
    if (!m) {
      log("a message from the station that does not decode: " + m.error());
      continue;
    }
    handle(m.value());
  }
}

void RobotClient::Impl::sendUpdates() {
  for (auto& [sequence, entry] : outbox) {
    const bool due = !entry.in_flight || secondsSince(entry.sent_at) > options.resend_s;
    if (!due) continue;
    if (!entry.in_flight && in_flight >= options.window) break;
    if (zstd && entry.packed.empty()) entry.packed = compressPayload(entry.payload);
    // Compressed only when it is smaller.
    const bool packed = zstd && entry.packed.size() < entry.payload.size();
    if (!send(update(options.epoch, sequence, packed ? entry.packed : entry.payload)))
      break;  // queue full: later
    (entry.ever_sent ? counts.resent : counts.sent) += 1;
    if (!entry.in_flight) ++in_flight;
    entry.in_flight = entry.ever_sent = true;
    entry.sent_at = Clock::now();
  }
}

RobotClient::RobotClient(RobotId robot, uint32_t provided_layers, RobotClientOptions options)
    : impl_(std::make_unique<Impl>(robot, provided_layers, std::move(options))) {}
RobotClient::~RobotClient() = default;

bool RobotClient::enqueue(const RobotUpdate& update) {
  Impl& c = *impl_;
  if (c.outbox.size() >= c.options.outbox_limit) return false;
  c.addToMap(update);
  // --full-resend: the whole map every time, as the paper's robots send it.
  const bool whole = c.options.full_resend && c.map_broken.empty();
  c.outbox[update.sequence] =
      entryOf(io::encodeRobotUpdateBinary(whole ? c.map.snapshot() : update));
  return true;
}

void RobotClient::fold(const RobotUpdate& update) { impl_->addToMap(update); }

void RobotClient::pump(std::chrono::milliseconds budget) {
  Impl& c = *impl_;
  const Clock::time_point end = Clock::now() + budget;
  do {
    if (!c.fatal.empty()) return;
    if (c.state == Impl::State::kDisconnected) {
      if (Clock::now() < c.reconnect_at) {
        std::this_thread::sleep_for(
            std::min<Clock::duration>(end - Clock::now(), c.reconnect_at - Clock::now()));
        continue;
      }
      c.connect();
      if (!c.fatal.empty()) return;
    }
    zmq::pollitem_t items[] = {{c.socket->handle(), 0, ZMQ_POLLIN, 0}};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
    interruptiblePoll(
        items, 1,
        std::max(std::chrono::milliseconds(0), std::min(left, std::chrono::milliseconds(50))));
    c.receive();
    if (!c.fatal.empty()) return;
    if (secondsSince(c.last_heard) > c.options.heartbeat_s * c.options.missed_heartbeats) {
      c.disconnect(c.state == Impl::State::kWelcomed ? "the station is silent"
                   : c.options.secret_key.empty()
                       ? "no WELCOME from the station"
                       : "no WELCOME from the station (does it know this robot's key?)");
      continue;
    }
    if (c.state == Impl::State::kWelcomed) c.sendUpdates();
    if (secondsSince(c.last_sent) >= c.options.heartbeat_s) c.send(heartbeat());
  } while (Clock::now() < end);
}

bool RobotClient::finish(std::chrono::milliseconds timeout) {
  Impl& c = *impl_;
  const Clock::time_point end = Clock::now() + timeout;
  // Every update acknowledged, then BYE until the station answers it (a BYE sent to a station
  // that restarted is refused, and the robot says HELLO again first).
  // A station that took every update may end before its answer to BYE arrives (a connection cut
  // at that moment): once every update is acknowledged, BYE is awaited for a while only.
  Clock::time_point bye_sent = Clock::now() - std::chrono::hours(1);
  std::optional<Clock::time_point> first_bye;
  const double bye_wait_s = 2.0 * c.options.heartbeat_s * c.options.missed_heartbeats;
  c.bye_answered = false;
  c.counts.bye_unanswered = false;
  while (c.fatal.empty() && Clock::now() < end && !c.bye_answered) {
    if (!c.outbox.empty()) first_bye.reset();  // e.g. a snapshot the station asked for on BYE
    if (c.outbox.empty() && first_bye && secondsSince(*first_bye) > bye_wait_s) {
      c.counts.bye_unanswered = true;
      c.log("every update is acknowledged; the station did not answer BYE within " +
            secondsText(bye_wait_s) + " s");
      break;
    }
    if (c.outbox.empty() && c.state == Impl::State::kWelcomed &&
        secondsSince(bye_sent) >= c.options.heartbeat_s) {
      c.send(bye());
      bye_sent = Clock::now();
      if (!first_bye) first_bye = bye_sent;
    }
    pump(std::chrono::milliseconds(50));
  }
  return (c.bye_answered || c.counts.bye_unanswered) && c.outbox.empty() && c.fatal.empty();
}

size_t RobotClient::unacknowledged() const { return impl_->outbox.size(); }
bool RobotClient::welcomed() const { return impl_->state == Impl::State::kWelcomed; }
const std::string& RobotClient::fatal() const { return impl_->fatal; }
const RobotClientCounts& RobotClient::counts() const { return impl_->counts; }

}  // namespace hydra_multi::net
