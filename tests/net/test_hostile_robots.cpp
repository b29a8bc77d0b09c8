// Hostile and broken robots on loopback (issue 23, item 3), each while robot b streams its whole
// map beside them: truncated frames and huge declared sizes, non-finite numbers, updates out of
// order, duplicated, from the future and of a previous epoch, a recorded connection played again,
// connections that say nothing (slowloris) and one that floods. For each: what the station counts
// and logs, and that robot b's map, and whatever else it held, is what it would be without them
// (the frontend digest). Garbage, other versions, oversized and corrupt messages and robots
// speaking for others are test_station_server.cpp's; unknown keys are its CURVE test's.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <limits>

#include "hydra_multi/dsg/io/binary_record.h"
#include "net/station_fixture.h"

namespace hydra_multi::net {
namespace {

using namespace test_support;

const RobotId kA(0), kB(1);

// Robot b streaming its whole map with a RobotClient, in a thread.
class Bystander {
 public:
  explicit Bystander(const std::string& endpoint)
      : thread_([this, endpoint] {
          RobotClient client(kB, kProvidesAll, clientOptions(endpoint));
          ok_ = sendStream(client, 1, 20s);
        }) {}
  ~Bystander() {
    if (thread_.joinable()) thread_.join();
  }
  bool join() {
    thread_.join();
    return ok_;
  }

 private:
  std::atomic<bool> ok_{false};
  std::thread thread_;
};

// The frontend digest of a station that took these updates, in this order, from a file.
uint64_t digestOf(const std::vector<RobotUpdate>& updates) {
  Station station{StationOptions{}};
  for (const RobotUpdate& u : updates) station.submit(u);
  return station.finish().frontend_digest;
}

std::vector<RobotUpdate> withStreamB(std::vector<RobotUpdate> updates) {
  updates.insert(updates.end(), tiny().streams[1].begin(), tiny().streams[1].end());
  return updates;
}

// Robot a's update `index` of the tiny team, as sequence `sequence` (encoded).
std::string payloadAs(size_t index, uint64_t sequence) {
  RobotUpdate u = tiny().streams[0][index];
  u.sequence = sequence;
  return io::encodeRobotUpdateBinary(u);
}

std::string varint(uint64_t v) {
  std::string out;
  while (v >= 0x80) {
    out += static_cast<char>((v & 0x7f) | 0x80);
    v >>= 7;
  }
  out += static_cast<char>(v);
  return out;
}

bool logged(Served& served, const std::string& text) {
  for (const std::string& line : served.log())
    if (line.find(text) != std::string::npos) return true;
  return false;
}

TEST(HostileRobot, TruncatedFramesAndHugeDeclaredSizes) {
  Served served(0);
  Bystander b(served.endpoint());
  RawPeer peer(served.endpoint());
  std::string json =
      "{\"robot\": \"a\", \"epoch\": 1, \"pad\": \"" + std::string(5000, 'x') + "\"}";
  std::vector<std::string> hello_frames = encodeMessage(hello(kA, 1, kProvidesAll));
  hello_frames[1] = json;
  peer.send(hello_frames);  // a JSON body past 4096 bytes
  Message m = peer.next();
  EXPECT_EQ(m.code, RefuseCode::kMalformed) << m.text;
  peer.send(encodeMessage(hello(kA, 1, kProvidesAll)));
  ASSERT_EQ(peer.next().type, MessageType::kWelcome);
  std::vector<std::string> cut = encodeMessage(update(1, 0, payloadOf(0, 0)));
  cut[0].resize(cut[0].size() - 3);  // a header cut short
  peer.send(cut);
  m = peer.next();
  EXPECT_EQ(m.code, RefuseCode::kMalformed);
  EXPECT_NE(m.text.find("bytes, not"), std::string::npos) << m.text;
  std::vector<std::string> bodiless = encodeMessage(update(1, 0, payloadOf(0, 0)));
  bodiless.pop_back();
  peer.send(bodiless);
  m = peer.next();
  EXPECT_EQ(m.code, RefuseCode::kMalformed);
  EXPECT_NE(m.text.find("frames, not"), std::string::npos) << m.text;
  const std::string whole = payloadOf(0, 0);
  peer.send(encodeMessage(update(1, 0, whole.substr(0, whole.size() / 2))));
  m = peer.next();
  EXPECT_EQ(m.code, RefuseCode::kBadPayload);
  EXPECT_EQ(m.text.rfind("UPDATE 0: payload: ", 0), 0u) << m.text;
  // A record that declares 2^60 bytes of payload, and one with a valid checksum whose first
  // count (the nodes it adds) is 2^50: refused before anything is allocated for them.
  std::string huge = "HMDG";
  huge += static_cast<char>(io::RecordKind::kRobotUpdate);
  huge += std::string("\x01\x00", 2);
  huge += varint(uint64_t{1} << 60) + std::string(64, '\0');
  peer.send(encodeMessage(update(1, 0, huge)));
  m = peer.next();
  EXPECT_EQ(m.code, RefuseCode::kBadPayload);
  EXPECT_EQ(m.sequence, 0u);
  const std::string counted = std::string(1, '\0') + varint(0) + varint(0) + std::string(1, '\0') +
                              varint(1) + varint(uint64_t{1} << 50) + std::string(32, '\0');
  peer.send(encodeMessage(update(1, 0, io::encodeRecord(io::RecordKind::kRobotUpdate, counted))));
  m = peer.next();
  EXPECT_EQ(m.code, RefuseCode::kBadPayload);
  EXPECT_NE(m.text.find("count"), std::string::npos) << m.text;
  // The same connection, well-formed now.
  peer.send(encodeMessage(update(1, 0, whole)));
  m = peer.next();
  EXPECT_EQ(m.type, MessageType::kAck);
  EXPECT_EQ(m.next_sequence, 1u);
  EXPECT_TRUE(b.join());
  const StationResult result = served.finish();
  const std::map<std::string, size_t> refused = {{"bad_payload", 3}, {"malformed", 3}};
  EXPECT_EQ(served.counts().refused, refused);
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB({tiny().streams[0][0]})));
}

TEST(HostileRobot, NonFiniteNumbersAreRefused) {
  Served served(0);
  Bystander b(served.endpoint());
  RawPeer peer(served.endpoint());
  peer.send(encodeMessage(hello(kA, 1, kProvidesAll)));
  ASSERT_EQ(peer.next().type, MessageType::kWelcome);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<RobotUpdate> broken(4, tiny().streams[0][0]);
  broken[0].graph.nodes.front().position.x() = nan;
  broken[1].graph.nodes.front().position.z() = -inf;
  ASSERT_FALSE(tiny().streams[0][1].pose_graph.empty());
  broken[2] = tiny().streams[0][1];
  broken[2].sequence = 0;
  broken[2].pose_graph.front().T_from_to.translation().y() = inf;
  broken[3].graph.mesh.vertices.push_back(
      broken[3].graph.mesh.vertices.empty() ? MeshVertex{} : broken[3].graph.mesh.vertices.front());
  broken[3].graph.mesh.vertices.back().position.x() = std::numeric_limits<float>::quiet_NaN();
  for (const RobotUpdate& u : broken) {
    peer.send(encodeMessage(update(1, 0, io::encodeRobotUpdateBinary(u))));
    const Message m = peer.next();
    EXPECT_EQ(m.code, RefuseCode::kBadPayload) << m.text;
    EXPECT_EQ(m.text.rfind("UPDATE 0: payload: ", 0), 0u) << m.text;
    EXPECT_NE(m.text.find("finite"), std::string::npos) << m.text;
  }
  EXPECT_TRUE(b.join());
  const StationResult result = served.finish();
  EXPECT_EQ(served.counts().refused.at("bad_payload"), broken.size());
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB({})));
}

TEST(HostileRobot, UpdatesOutOfOrderDuplicatedAndFromTheFuture) {
  StationServerOptions options;
  options.max_ahead = 3;
  options.gap_s = 60.0;  // no snapshot requests among the answers
  Served served(0, options);
  Bystander b(served.endpoint());
  RawPeer peer(served.endpoint());
  peer.send(encodeMessage(hello(kA, 1, kProvidesAll)));
  ASSERT_EQ(peer.next().type, MessageType::kWelcome);
  const auto send = [&](uint64_t sequence, const std::string& payload) {
    peer.send(encodeMessage(update(1, sequence, payload)));
    return peer.next();
  };
  // First update since HELLO is 2: the station asks for a snapshot, and holds it.
  Message m = send(2, payloadOf(0, 2));
  EXPECT_EQ(m.type, MessageType::kAck);
  EXPECT_EQ(peer.next().type, MessageType::kSnapshotRequest);
  EXPECT_EQ(send(1, payloadOf(0, 1)).next_sequence, 0u);
  EXPECT_EQ(send(0, payloadOf(0, 0)).next_sequence, 3u);  // 0, 1, 2 held
  m = send(1, payloadOf(0, 1));                           // a duplicate
  EXPECT_EQ(m.type, MessageType::kAck);
  EXPECT_EQ(m.next_sequence, 3u);
  // From the future: held beyond the missing update 3, up to max_ahead of them.
  for (uint64_t s = 1000; s < 1003; ++s) {
    m = send(s, payloadAs(3, s));
    EXPECT_EQ(m.type, MessageType::kAck) << m.text;
    EXPECT_EQ(m.next_sequence, 3u);
  }
  m = send(1003, payloadAs(3, 1003));
  EXPECT_EQ(m.code, RefuseCode::kTooFarAhead);
  EXPECT_EQ(m.text,
            "UPDATE 1003: the station holds 3 updates of robot a beyond missing update 3 "
            "already; a snapshot is due first");
  EXPECT_TRUE(b.join());
  const StationResult result = served.finish();
  EXPECT_EQ(served.counts().robots.at(kA).duplicates, 1u);
  EXPECT_EQ(served.counts().robots.at(kA).updates, 6u);
  EXPECT_EQ(served.counts().refused.at("too_far_ahead"), 1u);
  const std::vector<RobotUpdate>& a = tiny().streams[0];
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB({a[0], a[1], a[2]})));
}

TEST(HostileRobot, UpdatesAndHellosOfAPreviousEpoch) {
  Served served(0);
  Bystander b(served.endpoint());
  RawPeer current(served.endpoint()), old(served.endpoint()), next(served.endpoint());
  current.send(encodeMessage(hello(kA, 200, kProvidesAll)));
  ASSERT_EQ(current.next().type, MessageType::kWelcome);
  current.send(encodeMessage(update(100, 0, payloadOf(0, 0))));
  Message m = current.next();
  EXPECT_EQ(m.code, RefuseCode::kStaleEpoch);
  EXPECT_EQ(m.text, "UPDATE 0 of epoch 100 on a connection of epoch 200");
  current.send(encodeMessage(update(200, 0, payloadOf(0, 0))));
  EXPECT_EQ(current.next().next_sequence, 1u);
  old.send(encodeMessage(hello(kA, 100, kProvidesAll)));
  m = old.next();
  EXPECT_EQ(m.code, RefuseCode::kStaleEpoch);
  EXPECT_EQ(m.text,
            "HELLO for robot a of epoch 100, older than its current run's (200), which is "
            "connected: an old process, or a recorded connection played again");
  // A newer epoch is a new run of the robot: welcomed, and asked for a snapshot.
  next.send(encodeMessage(hello(kA, 300, kProvidesAll)));
  m = next.next();
  EXPECT_EQ(m.type, MessageType::kWelcome);
  EXPECT_EQ(next.next().type, MessageType::kSnapshotRequest);
  EXPECT_TRUE(b.join());
  const StationResult result = served.finish();
  EXPECT_EQ(served.counts().refused.at("stale_epoch"), 2u);
  EXPECT_TRUE(logged(served, "robot a connected again; connection"));
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB({tiny().streams[0][0]})));
}

TEST(HostileRobot, ReplayedRecordingOfAnOldConnection) {
  Served served(0);
  Bystander b(served.endpoint());
  RobotClientOptions a_options = clientOptions(served.endpoint());
  a_options.epoch = 500;
  {
    RobotClient a(kA, kProvidesAll, a_options);
    ASSERT_TRUE(sendStream(a, 0));
  }
  const std::vector<RobotUpdate>& stream = tiny().streams[0];
  // The connection as recorded: HELLO, every UPDATE, BYE, played again on a new connection.
  RawPeer replay(served.endpoint());
  replay.send(encodeMessage(hello(kA, 500, kProvidesAll)));
  Message m = replay.next();
  ASSERT_EQ(m.type, MessageType::kWelcome);
  for (size_t k = 0; k < stream.size(); ++k) {
    replay.send(encodeMessage(update(500, k, payloadOf(0, k))));
    m = replay.next();
    EXPECT_EQ(m.type, MessageType::kAck);
    EXPECT_EQ(m.next_sequence, stream.size());
  }
  replay.send(encodeMessage(bye()));
  EXPECT_EQ(replay.next().type, MessageType::kBye);
  // The same recording with an older epoch than the run that said BYE: refused.
  RawPeer older(served.endpoint());
  older.send(encodeMessage(hello(kA, 400, kProvidesAll)));
  m = older.next();
  EXPECT_EQ(m.code, RefuseCode::kStaleEpoch);
  EXPECT_NE(m.text.find("which said BYE"), std::string::npos) << m.text;
  EXPECT_TRUE(b.join());
  const StationResult result = served.finish();
  EXPECT_EQ(served.counts().robots.at(kA).duplicates, stream.size());
  EXPECT_EQ(served.counts().robots.at(kA).updates, stream.size());
  EXPECT_EQ(result.counts.appliedTotal(), stream.size() + tiny().streams[1].size());
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB(stream)));
}

// A TCP connection to the station's port on loopback (no ZeroMQ): true once the station closed
// it, within `timeout`.
bool closedByStation(int fd, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  timeval tv{0, 50000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  char buffer[256];
  while (std::chrono::steady_clock::now() < end) {
    const ssize_t n = recv(fd, buffer, sizeof(buffer), 0);
    if (n == 0) return true;                                            // closed
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) return true;  // reset
  }
  return false;
}

int connectTcp(const std::string& endpoint) {
  const int port = std::stoi(endpoint.substr(endpoint.rfind(':') + 1));
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

TEST(HostileRobot, SlowlorisConnectionsAreClosed) {
  StationServerOptions options;
  options.handshake_s = 0.5;
  options.heartbeat_s = 0.2;
  Served served(0, options);
  // Ten TCP connections that never finish ZeroMQ's handshake: five say nothing, five stop in the
  // middle of the greeting.
  std::vector<int> sockets;
  for (int k = 0; k < 10; ++k) {
    const int fd = connectTcp(served.endpoint());
    ASSERT_GE(fd, 0);
    if (k % 2 == 1) {
      ASSERT_EQ(send(fd, "\xff\0\0\0\0", 5, 0), 5);
    }
    sockets.push_back(fd);
  }
  // A connection that says HELLO and then nothing.
  RawPeer silent(served.endpoint());
  silent.send(encodeMessage(hello(kA, 1, kProvidesAll)));
  ASSERT_EQ(silent.next().type, MessageType::kWelcome);
  Bystander b(served.endpoint());
  for (const int fd : sockets) {
    EXPECT_TRUE(closedByStation(fd, 5s));
    close(fd);
  }
  EXPECT_TRUE(b.join());
  const auto end = std::chrono::steady_clock::now() + 3s;
  const std::string gone = "(robot a) silent for 0.6 s, taken as gone";
  while (!logged(served, gone) && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(50ms);
  const StationResult result = served.finish();
  EXPECT_TRUE(logged(served, gone));
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB({})));
}

TEST(HostileRobot, FloodIsThrottledWhileOthersGoOn) {
  StationServerOptions options;
  options.max_messages_per_s = 100.0;
  options.max_bytes_per_s = 20000.0;
  options.max_message_bytes = 64 << 10;  // the byte burst: one largest message
  Served served(0, options);
  Bystander b(served.endpoint());
  RawPeer flooder(served.endpoint()), heavy(served.endpoint());
  flooder.send(encodeMessage(hello(kA, 1, kProvidesAll)));
  ASSERT_EQ(flooder.next().type, MessageType::kWelcome);
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < 3000; ++k) flooder.send(encodeMessage(heartbeat()));
  // Bytes: 30 KB messages at 20 KB/s after a 64 KiB burst.
  for (int k = 0; k < 10; ++k) heavy.send({std::string(30000, 'x')});
  // Slowed down, the flooder is served again: throttled, not cut off.
  std::this_thread::sleep_for(1500ms);
  flooder.send(encodeMessage(update(1, 0, payloadOf(0, 0))));
  Message m = flooder.next();
  EXPECT_EQ(m.type, MessageType::kAck) << m.text;
  EXPECT_TRUE(b.join());
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const StationResult result = served.finish();
  const size_t limited = served.counts().refused.at("rate_limited");
  // At most the burst (200) and 100 per second went through of the 3000 heartbeats; of the ten
  // 30 KB messages, at most the burst (two) and 20 KB per second.
  EXPECT_GE(limited, 3000 - 200 - static_cast<size_t>(100 * elapsed) - 1 +
                         (10 - 2 - static_cast<size_t>(20000 * elapsed / 30000) - 1));
  EXPECT_TRUE(logged(served, "(robot a) sends faster than 100 messages/s"));
  EXPECT_TRUE(logged(served, "sends faster than 0.02 MB/s"));
  EXPECT_EQ(served.counts().robots.at(kB).updates, tiny().streams[1].size());
  EXPECT_EQ(result.frontend_digest, digestOf(withStreamB({tiny().streams[0][0]})));
}

}  // namespace
}  // namespace hydra_multi::net
