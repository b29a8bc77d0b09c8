// The station's network input and a robot's client on loopback: a robot's whole stream arrives,
// each update once; hostile and broken messages are refused with their reason while a robot goes
// on; a robot that starts before the station, or whose station restarts, connects when it can and
// loses nothing. Every test is bounded in time (a few seconds) and uses 127.0.0.1 only.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/net/keys.h"
#include "hydra_multi/net/payload.h"
#include "hydra_multi/net/protocol.h"
#include "hydra_multi/net/robot_client.h"
#include "hydra_multi/net/station_server.h"
#include "hydra_multi/sim/dataset.h"
#include "net/station_fixture.h"

namespace hydra_multi::net {
namespace {

using namespace std::chrono_literals;
using namespace test_support;

const RobotId kA(0), kB(1);

// Both robots of the tiny team over loopback: every update handed to the station once, all
// applied, both robots aligned.
TEST(StationServer, TwoRobotsStreamTheirMaps) {
  Served served(2);
  std::vector<std::thread> robots;
  std::atomic<int> finished{0};
  for (size_t r = 0; r < 2; ++r) {
    robots.emplace_back([&, r] {
      RobotClient client(RobotId(static_cast<uint8_t>(r)), kProvidesAll,
                         clientOptions(served.endpoint()));
      if (sendStream(client, r)) ++finished;
    });
  }
  for (std::thread& t : robots) t.join();
  EXPECT_EQ(finished.load(), 2);
  const StationResult result = served.finish();
  const size_t total = tiny().streams[0].size() + tiny().streams[1].size();
  EXPECT_EQ(result.counts.offered, total);
  EXPECT_EQ(result.counts.appliedTotal(), total);
  EXPECT_EQ(result.aligned.size(), 2u);
  EXPECT_EQ(served.counts().robots.at(kA).updates, tiny().streams[0].size());
  EXPECT_TRUE(served.counts().robots.at(kB).said_bye);
  EXPECT_TRUE(served.counts().refused.empty());
  // The station offers zstd and the robots take it: fewer bytes arrive than the records hold.
  size_t records = 0;
  for (size_t r = 0; r < 2; ++r) {
    for (const RobotUpdate& u : tiny().streams[r]) records += io::encodeRobotUpdateBinary(u).size();
  }
  EXPECT_LT(served.counts().bytes, records * 3 / 4);
}

// Garbage, another version, an update before HELLO, a robot speaking for another, an update whose
// payload does not decode, an oversized message and a compressed payload that would expand past
// the limit: each refused with its reason and counted,
// while robot b streams its whole map beside them.
TEST(StationServer, RefusesHostileMessagesWhileOthersGoOn) {
  StationServerOptions options;
  options.max_message_bytes = 1 << 20;
  Served served(0, options);
  std::thread robot_b([&] {
    RobotClient client(kB, kProvidesAll, clientOptions(served.endpoint()));
    EXPECT_TRUE(sendStream(client, 1));
  });
  RawPeer peer(served.endpoint());
  peer.send({"garbage"});
  Message m = peer.next();
  EXPECT_EQ(m.type, MessageType::kRefuse);
  EXPECT_EQ(m.text, "frame 0: not a hydra-multi message (no \"HM\" header)");
  std::vector<std::string> v9 = encodeMessage(heartbeat());
  v9[0][2] = 9;
  peer.send(v9);
  EXPECT_EQ(peer.next().text, "frame 0: protocol version 9, this station speaks 1");
  peer.send(encodeMessage(update(1, 0, payloadOf(0, 0))));
  m = peer.next();
  EXPECT_EQ(m.text, "UPDATE 0 before HELLO on this connection");
  EXPECT_EQ(m.sequence, kNoSequence);  // a request to say HELLO, not a refusal of the update
  EXPECT_EQ(m.code, RefuseCode::kNoHello);
  peer.send(encodeMessage(hello(kA, 1, kProvidesAll)));
  EXPECT_EQ(peer.next().type, MessageType::kWelcome);
  peer.send(encodeMessage(update(1, 0, payloadOf(1, 0))));  // robot b's update over a's link
  EXPECT_EQ(peer.next().text, "UPDATE 0 is robot b's, this connection speaks for robot a");
  std::string broken = payloadOf(0, 0);
  broken[broken.size() / 2] ^= 0x40;
  peer.send(encodeMessage(update(1, 0, broken)));
  m = peer.next();
  EXPECT_EQ(m.text.rfind("UPDATE 0: payload: ", 0), 0u) << m.text;
  peer.send(encodeMessage(update(1, 5, std::string(1 << 21, 'x'))));
  EXPECT_EQ(peer.next().text, "a message of 2097172 bytes, more than the limit of 1048576");
  // A small compressed payload that would expand past the limit: refused before it is expanded.
  peer.send(encodeMessage(update(1, 0, compressPayload(std::string(1 << 21, 'x')))));
  EXPECT_EQ(peer.next().text,
            "UPDATE 0: payload: zstd frame expands to 2097152 bytes, more than the limit of "
            "1048576");
  // The same connection, well-behaved now: its update is taken and acknowledged.
  peer.send(encodeMessage(update(1, 0, payloadOf(0, 0))));
  m = peer.next();
  EXPECT_EQ(m.type, MessageType::kAck);
  EXPECT_EQ(m.next_sequence, 1u);
  robot_b.join();
  const StationResult result = served.finish();
  const std::map<std::string, size_t> refused = {{"bad_payload", 2}, {"malformed", 1},
                                                 {"no_hello", 1},    {"too_large", 1},
                                                 {"version", 1},     {"wrong_robot", 1}};
  EXPECT_EQ(served.counts().refused, refused);
  EXPECT_EQ(result.counts.appliedTotal(), tiny().streams[1].size() + 1);
  size_t logged = 0;
  for (const std::string& line : served.log())
    logged += line.find("refused a message") != std::string::npos;
  EXPECT_EQ(logged, 7u);
}

// A robot that starts before its station keeps its updates, tries again with its backoff, and
// once the station is up is welcomed and sends them all: none is lost.
TEST(StationServer, RobotWaitsAndReconnects) {
  // A free port on loopback.
  std::string endpoint;
  {
    Station probe{StationOptions{}};
    endpoint = StationServer::create(probe, {}).value()->endpoint();
  }
  RobotClient client(kA, kProvidesAll, clientOptions(endpoint));
  const std::vector<RobotUpdate>& stream = tiny().streams[0];
  for (const RobotUpdate& u : stream) ASSERT_TRUE(client.enqueue(u));
  client.pump(300ms);  // nobody there yet
  EXPECT_FALSE(client.welcomed());
  StationServerOptions options;
  options.listen = endpoint;
  Served served(1, options);
  EXPECT_TRUE(client.finish(10s));
  EXPECT_TRUE(served.ended(5s));
  const StationResult result = served.finish();
  EXPECT_EQ(result.counts.appliedTotal(), stream.size());
  EXPECT_GE(client.counts().connections, 1u);
  EXPECT_EQ(client.counts().acknowledged, stream.size());
  EXPECT_EQ(client.counts().lost_acknowledged, 0u);
}

// A station that restarts without what it acknowledged (here: no journal) welcomes the robot
// with less than its ACKs promised: the robot counts and logs the loss, and the station's request
// for a snapshot still brings the whole map.
TEST(StationServer, RobotSaysWhenTheStationLostWhatItAcknowledged) {
  std::string endpoint;
  {
    Station probe{StationOptions{}};
    endpoint = StationServer::create(probe, {}).value()->endpoint();
  }
  RobotClientOptions client_options = clientOptions(endpoint);
  std::vector<std::string> client_log;
  client_options.log = [&client_log](const std::string& line) { client_log.push_back(line); };
  RobotClient client(kA, kProvidesAll, client_options);
  const std::vector<RobotUpdate>& stream = tiny().streams[0];
  ASSERT_GT(stream.size(), 4u);
  StationServerOptions options;
  options.listen = endpoint;
  {
    Served forgetful(0, options);
    for (size_t k = 0; k < 3; ++k) ASSERT_TRUE(client.enqueue(stream[k]));
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (client.counts().acknowledged < 3 && std::chrono::steady_clock::now() < deadline)
      client.pump(10ms);
    ASSERT_EQ(client.counts().acknowledged, 3u);
  }
  Served restarted(1, options);
  for (size_t k = 3; k < stream.size(); ++k) ASSERT_TRUE(client.enqueue(stream[k]));
  EXPECT_TRUE(client.finish(10s));
  EXPECT_EQ(client.counts().lost_acknowledged, 3u);
  EXPECT_TRUE(std::any_of(client_log.begin(), client_log.end(), [](const std::string& line) {
    return line.find("the station lost updates it had acknowledged") != std::string::npos;
  }));
  EXPECT_TRUE(restarted.ended(5s)) << [&] {
    std::string all;
    for (const auto& l : client_log) all += "robot: " + l + "\n";
    for (const auto& l : restarted.log()) all += "station: " + l + "\n";
    return all;
  }();
  Station whole{StationOptions{}};
  for (const RobotUpdate& u : stream) whole.submit(u);
  EXPECT_EQ(restarted.finish().frontend_digest, whole.finish().frontend_digest)
      << "the snapshot brings the whole map";
}

// Every status_s the station says how each robot is doing: connected, its updates, its bytes;
// once it said BYE, done.
TEST(StationServer, ProgressLinePerRobot) {
  StationServerOptions options;
  options.status_s = 0.2;
  Served served(0, options);
  RobotClient client(kA, kProvidesAll, clientOptions(served.endpoint()));
  for (size_t i = 0; i < 3; ++i) ASSERT_TRUE(client.enqueue(tiny().streams[0][i]));
  client.pump(500ms);
  EXPECT_EQ(client.unacknowledged(), 0u);
  ASSERT_TRUE(client.finish(5s));
  std::this_thread::sleep_for(300ms);
  served.stop();
  bool connected = false, done = false;
  for (const std::string& line : served.log()) {
    connected |= line.rfind("station: robot a: connected, 3 updates, ", 0) == 0 &&
                 line.find(" MB received") != std::string::npos;
    done |= line.rfind("station: robot a: done (BYE), 3 updates, ", 0) == 0;
  }
  EXPECT_TRUE(connected);
  EXPECT_TRUE(done);
}

// Nodes per layer of a graph, to compare maps.
std::map<Layer, size_t> nodesPerLayer(const SceneGraph& graph) {
  std::map<Layer, size_t> counts;
  for (const Layer layer : kAllLayers) counts[layer] = graph.numNodes(layer);
  return counts;
}

// The map of robot a's whole stream sent by one uninterrupted client.
const std::map<Layer, size_t>& uninterruptedMap() {
  static const std::map<Layer, size_t> map = [] {
    Served served(1);
    RobotClient client(kA, kProvidesAll, clientOptions(served.endpoint()));
    EXPECT_TRUE(sendStream(client, 0));
    return nodesPerLayer(served.finish().graph);
  }();
  return map;
}

// A robot process killed mid-mission and started again (a new epoch, an empty outbox): the new
// process's map holds what the old one made, also the updates it never sent; the station asks
// it for a snapshot, which brings those. Nothing is lost, nothing applied twice, and the map is
// the uninterrupted one.
TEST(StationServer, RestartedRobotIsRecoveredBySnapshot) {
  const std::vector<RobotUpdate>& stream = tiny().streams[0];
  ASSERT_GE(stream.size(), 12u);
  Served served(1);
  {
    RobotClientOptions first = clientOptions(served.endpoint());
    first.epoch = 1;
    RobotClient client(kA, kProvidesAll, first);
    for (size_t i = 0; i < 5; ++i) ASSERT_TRUE(client.enqueue(stream[i]));
    const auto end = std::chrono::steady_clock::now() + 5s;
    while (client.unacknowledged() > 0 && std::chrono::steady_clock::now() < end) client.pump(20ms);
    ASSERT_EQ(client.unacknowledged(), 0u);
  }  // killed: updates 5 to 9 are made while it is down, and never sent
  RobotClientOptions second = clientOptions(served.endpoint());
  second.epoch = 2;
  RobotClient client(kA, kProvidesAll, second);
  for (size_t i = 0; i < 10; ++i) client.fold(stream[i]);
  client.pump(300ms);  // welcomed, asked for a snapshot, sends it
  for (size_t i = 10; i < stream.size(); ++i) ASSERT_TRUE(client.enqueue(stream[i]));
  ASSERT_TRUE(client.finish(10s));
  ASSERT_TRUE(served.ended(5s));
  EXPECT_EQ(served.counts().snapshots_requested, 1u);
  EXPECT_EQ(client.counts().snapshots, 1u);
  size_t sent_snapshots = 0;  // of the stream's own, those sent (the first update is one)
  for (size_t i = 0; i < stream.size(); ++i)
    sent_snapshots += (i < 5 || i >= 10) && stream[i].is_snapshot;
  EXPECT_EQ(served.counts().robots.at(kA).snapshots, sent_snapshots + 1);
  EXPECT_EQ(served.counts().robots.at(kA).next_sequence, stream.size());
  const StationResult result = served.finish();
  EXPECT_EQ(result.counts.duplicates, 0u);
  EXPECT_EQ(result.counts.rejected, 0u);
  EXPECT_EQ(result.counts.behindGap(), 0u);
  EXPECT_EQ(result.counts.offered, result.counts.appliedTotal());
  // 5 before the kill, one snapshot for 5 to 9, then each later one.
  EXPECT_EQ(result.counts.appliedTotal(), 5u + 1u + (stream.size() - 10));
  EXPECT_EQ(nodesPerLayer(result.graph), uninterruptedMap());
}

// An update the robot made but never had in its outbox (lost on the robot): the station holds
// the later ones beyond the gap and asks for a snapshot (once the gap has stood for gap_s, or
// when the robot says BYE with it), and the snapshot fills it; the map is the uninterrupted one.
TEST(StationServer, GapIsFilledBySnapshot) {
  const std::vector<RobotUpdate>& stream = tiny().streams[0];
  StationServerOptions options;
  options.gap_s = 0.3;
  Served served(1, options);
  RobotClient client(kA, kProvidesAll, clientOptions(served.endpoint()));
  for (size_t i = 0; i < stream.size(); ++i) {
    if (i == 5)
      client.fold(stream[i]);
    else
      ASSERT_TRUE(client.enqueue(stream[i]));
    client.pump(0ms);
  }
  client.pump(1s);  // the gap stands for gap_s: the station asks, the robot answers
  ASSERT_TRUE(client.finish(10s));
  ASSERT_TRUE(served.ended(5s));
  EXPECT_EQ(served.counts().snapshots_requested, 1u);
  const StationResult result = served.finish();
  EXPECT_EQ(result.counts.rejected, 0u);
  EXPECT_EQ(result.counts.behindGap(), 0u);
  EXPECT_EQ(nodesPerLayer(result.graph), uninterruptedMap());
  bool asked = false;
  for (const std::string& line : served.log())
    asked |= line.find("asked robot a for a snapshot: update 5 is missing, " +
                       std::to_string(stream.size() - 6) + " later ones held, for 0.3 s") !=
             std::string::npos;
  EXPECT_TRUE(asked);
}

// CURVE: the station admits only the keys it knows, and a key speaks only for its robot. Robot
// a with its key streams its map; a robot with a key the station does not know is never welcomed;
// robot a's key saying HELLO for robot b is refused, which ends that robot's mission.
TEST(StationServer, CurveAdmitsKnownKeysForTheirRobotsOnly) {
  ASSERT_TRUE(curveAvailable());
  const KeyPair station_keys = generateKeyPair().value();
  const KeyPair a_keys = generateKeyPair().value(), stranger = generateKeyPair().value();
  StationServerOptions options;
  options.secret_key = station_keys.secret_z85;
  options.robot_keys = {{a_keys.public_z85, kA}};
  Served served(0, options);
  const auto curveOptions = [&](const KeyPair& keys) {
    RobotClientOptions o = clientOptions(served.endpoint());
    o.secret_key = keys.secret_z85;
    o.station_key = station_keys.public_z85;
    return o;
  };
  RobotClient unknown(kB, kProvidesAll, curveOptions(stranger));
  ASSERT_TRUE(unknown.enqueue(tiny().streams[1].front()));
  RobotClient impostor(kB, kProvidesAll, curveOptions(a_keys));
  ASSERT_TRUE(impostor.enqueue(tiny().streams[1].front()));
  RobotClient a(kA, kProvidesAll, curveOptions(a_keys));
  EXPECT_TRUE(sendStream(a, 0));
  for (int i = 0; i < 20; ++i) {
    unknown.pump(50ms);
    impostor.pump(50ms);
  }
  EXPECT_FALSE(unknown.welcomed());
  EXPECT_EQ(unknown.counts().acknowledged, 0u);
  EXPECT_EQ(impostor.fatal(), "the station refused: HELLO for robot b with robot a's key");
  const StationResult result = served.finish();
  EXPECT_EQ(result.counts.appliedTotal(), tiny().streams[0].size());
  EXPECT_GE(served.counts().refused.at("unknown_key"), 1u);
  EXPECT_EQ(served.counts().refused.at("wrong_robot"), 1u);
}

// Key files: written once (never over an existing key), read back, the secret only its owner's;
// a folder of robot keys maps each key to its file's robot, and refuses a file that is no
// robot's, a key that is not one, and a key two robots share.
TEST(Keys, FilesOfKeys) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "hydra_multi_keys_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "robots");
  const KeyPair keys = generateKeyPair().value();
  ASSERT_TRUE(writeKeyPair((dir / "a").string(), keys).ok());
  EXPECT_EQ(writeKeyPair((dir / "a").string(), keys).message(),
            (dir / "a.key").string() + ": exists already; not overwriting a key");
  EXPECT_EQ(fs::status(dir / "a.key").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(readKey((dir / "a.key").string()).value(), keys.secret_z85);
  EXPECT_EQ(publicKeyOf(keys.secret_z85).value(), keys.public_z85);
  fs::copy_file(dir / "a.pub", dir / "robots" / "a.pub");
  EXPECT_EQ(readRobotKeys((dir / "robots").string()).value(),
            (std::map<std::string, RobotId>{{keys.public_z85, kA}}));
  fs::copy_file(dir / "a.pub", dir / "robots" / "b.pub");
  EXPECT_EQ(readRobotKeys((dir / "robots").string()).error(),
            (dir / "robots" / "b.pub").string() + ": the same key as robot a's");
  fs::remove(dir / "robots" / "b.pub");
  std::ofstream(dir / "robots" / "station.pub") << keys.public_z85 << "\n";
  EXPECT_NE(
      readRobotKeys((dir / "robots").string()).error().find("'station' is not a robot's name"),
      std::string::npos);
  std::ofstream(dir / "bad.key") << "short\n";
  EXPECT_EQ(readKey((dir / "bad.key").string()).error(),
            (dir / "bad.key").string() +
                ": not a CURVE key (one line of 40 Z85 characters, as keygen writes)");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hydra_multi::net
