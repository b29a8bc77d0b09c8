#include "hydra_multi/net/station_server.h"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/net/clock.h"
#include "hydra_multi/net/interruptible_poll.h"
#include "hydra_multi/net/payload.h"
#include "hydra_multi/net/protocol.h"

namespace hydra_multi::net {
namespace {

// A connection: what its HELLO said, and when it was last heard and sent to.
struct Session {
  size_t number = 0;                 // for logs: "connection 3"
  std::optional<RobotId> key_robot;  // with CURVE: the robot whose key the connection holds
  bool welcomed = false;
  RobotId robot;
  uint64_t epoch = 0;
  bool updated = false;  // an UPDATE arrived since the WELCOME
  Clock::time_point last_heard = Clock::now(), last_sent = Clock::now();
  // The rate limit's token buckets (messages, bytes), when they were last filled, and the
  // messages dropped since the last log line about them.
  bool buckets_filled = false;
  double message_tokens = 0.0, byte_tokens = 0.0;
  Clock::time_point filled = Clock::now(), rate_logged = Clock::now() - std::chrono::hours(1);
  size_t dropped = 0;
};

// The updates of a robot the station holds: every one before `next`, and those in `ahead`; the
// epoch of the robot process that last said HELLO (0: none yet), and when `next` last moved.
struct Held {
  uint64_t next = 0;
  std::set<uint64_t> ahead;
  uint64_t epoch = 0;
  Clock::time_point progress = Clock::now(), requested = Clock::now() - std::chrono::hours(1);
  Clock::time_point heard = Clock::now();  // the robot's last message, on any connection
  bool empty() const { return next == 0 && ahead.empty(); }
  bool has(uint64_t sequence) const { return sequence < next || ahead.count(sequence) > 0; }
  // Held already: a delta it holds, or a snapshot that covers nothing new.
  bool holds(uint64_t sequence, bool snapshot) const {
    return snapshot ? sequence < next : has(sequence);
  }
  void add(uint64_t sequence, bool snapshot) {
    const uint64_t before = next;
    if (snapshot && sequence >= next) {  // a snapshot stands for everything before it
      next = sequence + 1;
      ahead.erase(ahead.begin(), ahead.lower_bound(next));
    } else {
      ahead.insert(sequence);
    }
    while (!ahead.empty() && *ahead.begin() <= next) {
      if (*ahead.begin() == next) ++next;
      ahead.erase(ahead.begin());
    }
    if (next != before) progress = Clock::now();
  }
};

}  // namespace

struct StationServer::Impl {
  Impl(Station& s, StationServerOptions o)
      : station(s),
        options(std::move(o)),
        socket(context, zmq::socket_type::router),
        zap(context, zmq::socket_type::rep) {}

  void log(const std::string& line) const {
    if (options.log) options.log(line);
  }
  void send(const std::string& id, Session& session, const Message& message);
  void refuse(const std::string& id, Session& session, RefuseCode code, const std::string& reason,
              uint64_t sequence = kNoSequence);
  void handle(const std::string& id, const std::vector<std::string>& frames);
  /// Whether a message of `bytes` from this connection is within its rate limit (taking its
  /// tokens if so); one that is not is counted and, once a second, logged.
  bool withinRate(Session& session, size_t bytes);
  void onHello(const std::string& id, Session& session, const Message& m);
  void onUpdate(const std::string& id, Session& session, const Message& m);
  void requestSnapshot(const std::string& id, Session& session, const std::string& why);
  void housekeeping();
  void status();        // one progress line per robot
  void refreshLinks();  // the copy links() returns
  void authenticate();  // answers one ZAP request
  std::string who(const Session& s) const {
    return "connection " + std::to_string(s.number) +
           (s.welcomed ? " (robot " + s.robot.str() + ")" : std::string());
  }

  Station& station;
  StationServerOptions options;
  zmq::context_t context;
  zmq::socket_t socket;
  zmq::socket_t zap;  // the ZAP handler's, with CURVE
  bool curve = false;
  std::string endpoint;
  std::map<std::string, Session> sessions;  // by ZeroMQ routing id
  size_t connections = 0;
  std::map<RobotId, Held> held;
  StationServerCounts counts;
  Clock::time_point last_status = Clock::now();
  mutable std::mutex links_mutex;
  std::map<RobotId, RobotLinkState> links;
};

void StationServer::Impl::refreshLinks() {
  std::map<RobotId, RobotLinkState> now;
  const double gone_s = options.heartbeat_s * options.missed_heartbeats;
  for (const auto& [robot, c] : counts.robots) {
    RobotLinkState& link = now[robot];
    link.silent_s = secondsSince(held[robot].heard);
    for (const auto& [id, session] : sessions)
      link.connected |= session.welcomed && session.robot == robot && link.silent_s < gone_s;
    link.said_bye = c.said_bye;
    link.bytes = c.bytes;
  }
  std::lock_guard<std::mutex> lock(links_mutex);
  links = std::move(now);
}

void StationServer::Impl::send(const std::string& id, Session& session, const Message& message) {
  std::vector<zmq::message_t> parts;
  parts.emplace_back(id.data(), id.size());
  for (const std::string& frame : encodeMessage(message))
    parts.emplace_back(frame.data(), frame.size());
  // A peer that went away, or whose queue is full, misses this message; the protocol recovers.
  (void)zmq::send_multipart(socket, parts, zmq::send_flags::dontwait);
  session.last_sent = Clock::now();
}

void StationServer::Impl::refuse(const std::string& id, Session& session, RefuseCode code,
                                 const std::string& reason, uint64_t sequence) {
  ++counts.refused[refuseCodeName(code)];
  log("station: refused a message from " + who(session) + ": " + reason);
  send(id, session, net::refuse(code, reason, session.epoch, sequence));
}

void StationServer::Impl::authenticate() {
  std::vector<zmq::message_t> request;
  if (!zmq::recv_multipart(zap, std::back_inserter(request), zmq::recv_flags::dontwait)) return;
  // ZAP (ZeroMQ RFC 27): version, request id, domain, address, routing id, mechanism, then the
  // client's public key for CURVE.
  std::string status = "400", text = "malformed request", user;
  if (request.size() >= 7 && request[5].to_string() == "CURVE" && request[6].size() == 32) {
    char key[41];
    zmq_z85_encode(key, static_cast<const uint8_t*>(request[6].data()), 32);
    const auto it = options.robot_keys.find(key);
    if (it != options.robot_keys.end()) {
      status = "200";
      text = "OK";
      user = it->second.str();
    } else {
      text = "unknown key";
      ++counts.refused["unknown_key"];
      log("station: refused a connection from " + request[3].to_string() + ": unknown key " + key);
    }
  }
  std::vector<zmq::message_t> reply;
  reply.emplace_back(std::string("1.0"));
  reply.emplace_back(request.size() > 1 ? request[1].to_string() : std::string());
  reply.emplace_back(status);
  reply.emplace_back(text);
  reply.emplace_back(user);
  reply.emplace_back(std::string());
  (void)zmq::send_multipart(zap, reply);
}

void StationServer::Impl::onHello(const std::string& id, Session& session, const Message& m) {
  if (options.other_inputs.count(m.robot))
    return refuse(id, session, RefuseCode::kWrongRobot,
                  "HELLO for robot " + m.robot.str() +
                      ", whose updates the station takes from another input (--spark-robot)");
  if (session.key_robot && *session.key_robot != m.robot)
    return refuse(
        id, session, RefuseCode::kWrongRobot,
        "HELLO for robot " + m.robot.str() + " with robot " + session.key_robot->str() + "'s key");
  // An older run of the robot than the one connected now or done: a process that should have
  // ended, or a recorded connection played again. (With the current run gone, an older epoch is
  // taken as a new run: a robot whose clock went back.)
  if (const Held& current = held[m.robot]; m.epoch < current.epoch) {
    const bool connected = std::any_of(sessions.begin(), sessions.end(), [&](const auto& s) {
      return s.first != id && s.second.welcomed && s.second.robot == m.robot;
    });
    const bool done = counts.robots[m.robot].said_bye;
    if (connected || done)
      return refuse(id, session, RefuseCode::kStaleEpoch,
                    "HELLO for robot " + m.robot.str() + " of epoch " + std::to_string(m.epoch) +
                        ", older than its current run's (" + std::to_string(current.epoch) +
                        "), which " + (connected ? "is connected" : "said BYE") +
                        ": an old process, or a recorded connection played again");
  }
  // Another live connection of the same robot is taken over by this one (a robot that
  // reconnected before the station noticed the old connection was gone).
  for (auto it = sessions.begin(); it != sessions.end();) {
    if (it->first != id && it->second.welcomed && it->second.robot == m.robot) {
      log("station: robot " + m.robot.str() + " connected again; " + who(it->second) +
          " is closed");
      it = sessions.erase(it);
    } else {
      ++it;
    }
  }
  session.welcomed = true;
  session.robot = m.robot;
  session.epoch = m.epoch;
  RobotLinkCounts& robot = counts.robots[m.robot];
  ++robot.connections;
  // A robot that said BYE and comes back with the same epoch is the same mission saying HELLO
  // again (its answer to BYE was lost); a new epoch is a new run of the robot's process.
  if (m.epoch != held[m.robot].epoch) robot.said_bye = false;
  Held& h = held[m.robot];
  log("station: robot " + m.robot.str() + " connected (" + who(session) + ", epoch " +
      std::to_string(m.epoch) + "), next update " + std::to_string(h.next));
  session.updated = false;
  send(id, session, welcome(h.next, options.accept_zstd));
  // A new run of a robot process the station holds updates of: what it lost with its outbox
  // only a snapshot of its map can bring back.
  const bool restarted = h.epoch != 0 && h.epoch != m.epoch && !h.empty();
  h.epoch = m.epoch;
  if (restarted) requestSnapshot(id, session, "it restarted (a new epoch)");
}

void StationServer::Impl::requestSnapshot(const std::string& id, Session& session,
                                          const std::string& why) {
  Held& h = held[session.robot];
  h.requested = Clock::now();
  ++counts.snapshots_requested;
  ++counts.robots[session.robot].snapshots_requested;
  log("station: asked robot " + session.robot.str() + " for a snapshot: " + why +
      "; it holds every update before " + std::to_string(h.next));
  send(id, session, snapshotRequest(session.epoch, h.next));
}

void StationServer::Impl::onUpdate(const std::string& id, Session& session, const Message& m) {
  // No HELLO on this connection: a robot whose station restarted under it (ZeroMQ reconnects by
  // itself). Refused without a sequence, which asks the robot to say HELLO again; its update is
  // not dropped.
  if (!session.welcomed)
    return refuse(id, session, RefuseCode::kNoHello,
                  "UPDATE " + std::to_string(m.sequence) + " before HELLO on this connection");
  if (m.epoch != session.epoch)
    return refuse(id, session, RefuseCode::kStaleEpoch,
                  "UPDATE " + std::to_string(m.sequence) + " of epoch " + std::to_string(m.epoch) +
                      " on a connection of epoch " + std::to_string(session.epoch),
                  m.sequence);
  auto record = expandPayload(m.payload, options.max_message_bytes);
  if (!record)
    return refuse(id, session, RefuseCode::kBadPayload,
                  "UPDATE " + std::to_string(m.sequence) + ": payload: " + record.error(),
                  m.sequence);
  auto decoded = io::decodeRobotUpdateBinary(record.value());
  if (!decoded)
    return refuse(id, session, RefuseCode::kBadPayload,
                  "UPDATE " + std::to_string(m.sequence) + ": payload: " + decoded.error(),
                  m.sequence);
  const RobotUpdate& u = decoded.value();
  if (u.robot != session.robot)
    return refuse(id, session, RefuseCode::kWrongRobot,
                  "UPDATE " + std::to_string(m.sequence) + " is robot " + u.robot.str() +
                      "'s, this connection speaks for robot " + session.robot.str(),
                  m.sequence);
  if (u.sequence != m.sequence)
    return refuse(
        id, session, RefuseCode::kMalformed,
        "UPDATE " + std::to_string(m.sequence) + " carries update " + std::to_string(u.sequence),
        m.sequence);
  RobotLinkCounts& robot = counts.robots[session.robot];
  Held& h = held[session.robot];
  const bool first = !session.updated;
  session.updated = true;
  if (h.holds(u.sequence, u.is_snapshot)) {
    ++robot.duplicates;
  } else {
    if (!u.is_snapshot && u.sequence > h.next && h.ahead.size() >= options.max_ahead)
      return refuse(id, session, RefuseCode::kTooFarAhead,
                    "UPDATE " + std::to_string(m.sequence) + ": the station holds " +
                        std::to_string(h.ahead.size()) + " updates of robot " +
                        session.robot.str() + " beyond missing update " + std::to_string(h.next) +
                        " already; a snapshot is due first",
                    m.sequence);
    if (options.persist) {
      const size_t wire = updateFramingBytes() + m.payload.size();
      if (Status stored = options.persist(u, session.epoch, record.value(), wire); !stored)
        return refuse(id, session, RefuseCode::kNotStored,
                      "UPDATE " + std::to_string(m.sequence) +
                          ": the station cannot store it: " + stored.message(),
                      m.sequence);
    }
    const bool snapshot = u.is_snapshot;
    station.submit(std::move(decoded).value());
    ++robot.updates;
    robot.snapshots += snapshot ? 1 : 0;
    h.add(m.sequence, snapshot);
  }
  robot.next_sequence = h.next;
  send(id, session, ack(session.epoch, m.sequence, h.next));
  // A robot sends its outbox in order from what WELCOME said the station holds: a first update
  // past `next` means the robot has no longer got the ones between.
  if (first && m.sequence > h.next && !u.is_snapshot)
    requestSnapshot(id, session,
                    "its first update since HELLO is " + std::to_string(m.sequence) +
                        ", and the station lacks " + std::to_string(h.next));
}

bool StationServer::Impl::withinRate(Session& session, size_t bytes) {
  const double messages_rate = options.max_messages_per_s, bytes_rate = options.max_bytes_per_s;
  if (messages_rate <= 0.0 && bytes_rate <= 0.0) return true;
  const double message_burst = 2.0 * messages_rate;
  const double byte_burst = std::max(2.0 * bytes_rate, double(options.max_message_bytes));
  const Clock::time_point now = Clock::now();
  if (!session.buckets_filled) {  // a new connection: full buckets
    session.buckets_filled = true;
    session.message_tokens = message_burst;
    session.byte_tokens = byte_burst;
  } else {
    const double elapsed = std::chrono::duration<double>(now - session.filled).count();
    session.message_tokens =
        std::min(message_burst, session.message_tokens + elapsed * messages_rate);
    session.byte_tokens = std::min(byte_burst, session.byte_tokens + elapsed * bytes_rate);
  }
  session.filled = now;
  const bool messages_ok = messages_rate <= 0.0 || session.message_tokens >= 1.0;
  const bool bytes_ok = bytes_rate <= 0.0 || session.byte_tokens >= double(bytes);
  if (messages_ok && bytes_ok) {
    if (messages_rate > 0.0) session.message_tokens -= 1.0;
    if (bytes_rate > 0.0) session.byte_tokens -= double(bytes);
    return true;
  }
  ++counts.refused[refuseCodeName(RefuseCode::kRateLimited)];
  ++session.dropped;
  if (secondsSince(session.rate_logged) >= 1.0) {
    std::ostringstream limit;
    if (!messages_ok) limit << messages_rate << " messages/s";
    if (!bytes_ok) limit << (messages_ok ? "" : " and ") << bytes_rate / 1e6 << " MB/s";
    log("station: " + who(session) + " sends faster than " + limit.str() + ": " +
        std::to_string(session.dropped) + " messages dropped unread since the last such line");
    session.rate_logged = now;
    session.dropped = 0;
  }
  return false;
}

void StationServer::Impl::handle(const std::string& id, const std::vector<std::string>& frames) {
  Session& session = sessions[id];
  if (session.number == 0) session.number = ++connections;
  session.last_heard = Clock::now();
  size_t bytes = 0;
  for (const std::string& f : frames) bytes += f.size();
  counts.bytes += bytes;
  if (!withinRate(session, bytes)) return;
  if (session.welcomed) {
    counts.robots[session.robot].bytes += bytes;
    held[session.robot].heard = Clock::now();
  }
  if (bytes > options.max_message_bytes)
    return refuse(id, session, RefuseCode::kTooLarge,
                  "a message of " + std::to_string(bytes) + " bytes, more than the limit of " +
                      std::to_string(options.max_message_bytes));
  auto message = decodeMessage(frames);
  if (!message) {
    const bool version = !frames.empty() && frames[0].size() >= 3 &&
                         frames[0].compare(0, 2, "HM") == 0 &&
                         static_cast<uint8_t>(frames[0][2]) != kProtocolVersion;
    return refuse(id, session, version ? RefuseCode::kVersion : RefuseCode::kMalformed,
                  message.error());
  }
  const Message& m = message.value();
  switch (m.type) {
    case MessageType::kHello:
      return onHello(id, session, m);
    case MessageType::kUpdate:
      return onUpdate(id, session, m);
    case MessageType::kHeartbeat:
      return;
    case MessageType::kBye: {
      if (!session.welcomed) return refuse(id, session, RefuseCode::kNoHello, "BYE before HELLO");
      // A mission cannot end with a gap: the robot is asked for a snapshot and says BYE again.
      const Held& h = held[session.robot];
      if (!h.ahead.empty()) {
        if (secondsSince(h.requested) > options.heartbeat_s)
          requestSnapshot(id, session,
                          "it said BYE, and update " + std::to_string(h.next) + " is missing");
        return;
      }
      if (options.persist_bye) {
        if (Status stored = options.persist_bye(session.robot, session.epoch); !stored) {
          log("station: robot " + session.robot.str() +
              " said BYE; the station cannot store it, and does not answer: " + stored.message());
          return;
        }
      }
      counts.robots[session.robot].said_bye = true;
      station.endOfStream(session.robot);
      log("station: robot " + session.robot.str() + " said BYE (" +
          std::to_string(counts.robots[session.robot].updates) + " updates)");
      send(id, session, bye());  // the answer the robot waits for
      sessions.erase(id);
      return;
    }
    default:
      return refuse(id, session, RefuseCode::kMalformed,
                    std::string(messageTypeName(m.type)) + " is the station's to send");
  }
}

void StationServer::Impl::status() {
  for (const auto& [robot, c] : counts.robots) {
    bool connected = false;
    for (const auto& [id, session] : sessions)
      connected |= session.welcomed && session.robot == robot;
    const double silent = secondsSince(held[robot].heard);
    std::ostringstream line;
    line.setf(std::ios::fixed);
    line.precision(2);
    line << "station: robot " << robot.str() << ": "
         << (c.said_bye ? std::string("done (BYE)")
             : connected && silent < options.heartbeat_s * options.missed_heartbeats
                 ? std::string("connected")
                 : "silent for " + std::to_string(static_cast<int>(silent)) + " s")
         << ", " << c.updates << " updates, " << double(c.bytes) / 1e6 << " MB received";
    log(line.str());
  }
}

void StationServer::Impl::housekeeping() {
  refreshLinks();
  if (options.status_s > 0.0 && secondsSince(last_status) >= options.status_s) {
    last_status = Clock::now();
    status();
  }
  const double gone_s = options.heartbeat_s * options.missed_heartbeats;
  for (auto it = sessions.begin(); it != sessions.end();) {
    Session& s = it->second;
    if (secondsSince(s.last_heard) > gone_s) {
      log("station: " + who(s) + " silent for " + secondsText(gone_s) + " s, taken as gone");
      it = sessions.erase(it);
      continue;
    }
    // A gap that resends have not filled: the robot has lost what is missing.
    if (s.welcomed) {
      const Held& h = held[s.robot];
      if (!h.ahead.empty() && secondsSince(h.progress) > options.gap_s &&
          secondsSince(h.requested) > options.gap_s)
        requestSnapshot(it->first, s,
                        "update " + std::to_string(h.next) + " is missing, " +
                            std::to_string(h.ahead.size()) + " later ones held, for " +
                            secondsText(options.gap_s) + " s");
    }
    if (secondsSince(s.last_sent) >= options.heartbeat_s) send(it->first, s, heartbeat());
    ++it;
  }
}

Result<std::unique_ptr<StationServer>> StationServer::create(Station& station,
                                                             StationServerOptions options) {
  auto impl = std::make_unique<Impl>(station, std::move(options));
  try {
    impl->socket.set(zmq::sockopt::linger, 0);
    if (!impl->options.secret_key.empty()) {
      if (!zmq_has("curve")) return Error{"this ZeroMQ library has no CURVE (no libsodium)"};
      // The ZAP handler is bound before the socket that asks it, in the same context.
      impl->zap.set(zmq::sockopt::linger, 0);
      impl->zap.bind("inproc://zeromq.zap.01");
      impl->socket.set(zmq::sockopt::curve_server, true);
      impl->socket.set(zmq::sockopt::curve_secretkey, impl->options.secret_key);
      impl->socket.set(zmq::sockopt::zap_domain, "hydra-multi");
      impl->curve = true;
    }
    // A hard cap well above the refusal limit: libzmq drops larger messages (and their sender)
    // before they reach the station, which could not say why.
    impl->socket.set(zmq::sockopt::handshake_ivl,
                     static_cast<int>(std::max(1.0, impl->options.handshake_s * 1000.0)));
    impl->socket.set(zmq::sockopt::maxmsgsize,
                     static_cast<int64_t>(2 * impl->options.max_message_bytes + (1 << 20)));
    impl->socket.bind(impl->options.listen);
    impl->endpoint = impl->socket.get(zmq::sockopt::last_endpoint);
  } catch (const zmq::error_t& e) {
    return Error{impl->options.listen + ": cannot listen: " + e.what()};
  }
  return std::unique_ptr<StationServer>(new StationServer(std::move(impl)));
}

StationServer::StationServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
StationServer::~StationServer() = default;

const std::string& StationServer::endpoint() const { return impl_->endpoint; }
const StationServerCounts& StationServer::counts() const { return impl_->counts; }

std::map<RobotId, RobotLinkState> StationServer::links() const {
  std::lock_guard<std::mutex> lock(impl_->links_mutex);
  return impl_->links;
}

void StationServer::hold(RobotId robot, uint64_t epoch, uint64_t sequence, bool snapshot) {
  Held& h = impl_->held[robot];
  if (!h.holds(sequence, snapshot)) h.add(sequence, snapshot);
  h.epoch = epoch;
  impl_->counts.robots[robot].next_sequence = h.next;
}

void StationServer::holdDone(RobotId robot, uint64_t epoch) {
  impl_->held[robot].epoch = epoch;
  impl_->counts.robots[robot].said_bye = true;
  impl_->station.endOfStream(robot);
}

void StationServer::serve(const std::function<bool()>& stop, size_t expect_robots) {
  Impl& s = *impl_;
  const auto byes = [&] {
    size_t n = 0;
    for (const auto& [robot, c] : s.counts.robots) n += c.said_bye ? 1 : 0;
    return n;
  };
  std::optional<Clock::time_point> all_byes;
  while (!(stop && stop())) {
    zmq::pollitem_t items[] = {{s.socket.handle(), 0, ZMQ_POLLIN, 0},
                               {s.zap.handle(), 0, ZMQ_POLLIN, 0}};
    // A signal (SIGINT, SIGTERM: the caller's stop) interrupts the wait; the loop asks stop().
    if (!interruptiblePoll(items, s.curve ? 2 : 1, std::chrono::milliseconds(100))) continue;
    if (s.curve && (items[1].revents & ZMQ_POLLIN)) s.authenticate();
    // Everything that arrived, a bounded number at a time so that heartbeats still go out.
    for (int i = 0; i < 1000; ++i) {
      std::vector<zmq::message_t> parts;
      if (!zmq::recv_multipart(s.socket, std::back_inserter(parts), zmq::recv_flags::dontwait))
        break;
      if (parts.empty()) continue;
      const std::string id = parts.front().to_string();
      std::vector<std::string> frames;
      for (size_t k = 1; k < parts.size(); ++k) frames.push_back(parts[k].to_string());
      if (s.curve && parts.size() > 1) {
        // The robot of the key the ZAP handler admitted this connection with.
        Session& session = s.sessions[id];
        if (!session.key_robot) {
          try {
            session.key_robot = RobotId::parse(parts[1].gets("User-Id"));
          } catch (const zmq::error_t&) {
          }
        }
      }
      s.handle(id, frames);
    }
    s.housekeeping();
    // Every expected robot said BYE: one heartbeat more, to answer a BYE sent again by a robot
    // whose answer was lost with a connection.
    if (expect_robots > 0 && byes() >= expect_robots) {
      if (!all_byes) all_byes = Clock::now();
      if (secondsSince(*all_byes) >= s.options.heartbeat_s) break;
    } else {
      all_byes.reset();
    }
  }
}

}  // namespace hydra_multi::net
