// Hydra robots as station inputs on loopback (net/hydra_robots.h): a plain PUB, as Hydra's
// ZmqSink, sends garbage, a cut message and then the real apartment graph as Spark-DSG put it on
// the wire; the bad ones are refused with the robot, the graph's number and the byte, the good
// one becomes robot a's update; a robot that stops sending is silent, then done; a HELLO on the
// station's protocol for a robot taken from Hydra is refused. Bounded to a few seconds each.

#include <gtest/gtest.h>

#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "hydra_multi/net/hydra_robots.h"
#include "hydra_multi/net/protocol.h"
#include "hydra_multi/net/station_server.h"

namespace hydra_multi::net {
namespace {

using namespace std::chrono_literals;

const RobotId kA(0), kB(1);

std::string fixture(const std::string& name) {
  std::ifstream in(std::string(HYDRA_MULTI_DATA_DIR) + "/spark/" + name, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A Hydra robot's sink: a PUB bound on a free loopback port.
class Sink {
 public:
  Sink() : pub_(context_, zmq::socket_type::pub) {
    pub_.set(zmq::sockopt::linger, 0);
    pub_.bind("tcp://127.0.0.1:*");
    endpoint_ = pub_.get(zmq::sockopt::last_endpoint);
  }
  const std::string& endpoint() const { return endpoint_; }
  void send(const std::string& bytes) {
    (void)pub_.send(zmq::buffer(bytes), zmq::send_flags::none);
  }

 private:
  zmq::context_t context_;
  zmq::socket_t pub_;
  std::string endpoint_;
};

template <typename Predicate>
bool within(std::chrono::milliseconds timeout, Predicate done) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!done() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(10ms);
  return done();
}

TEST(HydraRobots, RefusesWhatIsNotAGraphAndTakesTheNext) {
  Sink sink;
  Station station(StationOptions{});
  std::mutex mutex;
  std::vector<std::string> log;
  HydraRobotsOptions options;
  options.robots = {{kA, sink.endpoint()}};
  options.done_after_s = 0.5;
  options.status_s = 0.0;
  options.log = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex);
    log.push_back(line);
  };
  std::vector<std::pair<uint64_t, size_t>> stored;
  options.persist = [&](const RobotUpdate& u, const std::string& record, size_t wire_bytes) {
    EXPECT_FALSE(record.empty());
    stored.emplace_back(u.sequence, wire_bytes);
    return Status::Ok();
  };
  auto robots = HydraRobots::create(station, options).value();
  robots->start();
  // The SUB joins late (ZeroMQ's slow joiner): garbage until it is heard.
  ASSERT_TRUE(within(5s, [&] {
    sink.send("garbage");
    std::this_thread::sleep_for(20ms);
    return robots->counts().at(kA).graphs > 0;
  }));
  const std::string wire = fixture("apartment.zmq.bin");
  ASSERT_EQ(wire.size(), 1015503u);
  const auto logged = [&](const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex);
    for (const std::string& line : log) {
      if (line.find(text) != std::string::npos) return true;
    }
    return false;
  };
  sink.send(wire.substr(0, 5000));  // cut short
  // Refused before the next graph is sent (a graph still waiting when a newer one comes is
  // overtaken, not decoded; counting refusals could count garbage still on its way).
  ASSERT_TRUE(within(2s, [&] { return logged("(5000 bytes): spark binary"); }));
  EXPECT_GE(robots->counts().at(kA).refused, 2u);
  sink.send(wire);
  ASSERT_TRUE(within(3s, [&] { return robots->counts().at(kA).updates == 1; }));
  EXPECT_TRUE(robots->links().at(kA).connected);
  EXPECT_FALSE(robots->links().at(kA).said_bye);
  sink.send(wire);  // the same graph again: nothing new
  ASSERT_TRUE(within(3s, [&] { return robots->counts().at(kA).unchanged == 1; }));
  // Silent, then done (and said so).
  ASSERT_TRUE(within(3s, [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return !log.empty() && log.back().find("nothing for 0.5 s; taken as done") != std::string::npos;
  }));
  EXPECT_EQ(robots->done(), 1u);
  EXPECT_TRUE(robots->links().at(kA).said_bye);
  robots->stop();
  const HydraRobotCounts c = robots->counts().at(kA);
  EXPECT_EQ(c.graphs, c.refused + c.updates + c.unchanged + c.overtaken);
  EXPECT_EQ(c.snapshots, 1u);
  EXPECT_EQ(c.next_sequence, 1u);
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(stored[0], std::make_pair(uint64_t{0}, wire.size()));
  const StationResult result = station.finish();
  EXPECT_EQ(result.counts.appliedTotal(), 1u);
  EXPECT_EQ(result.graph.numNodes(Layer::kAgents), 102u);
  EXPECT_EQ(result.graph.numNodes(Layer::kObjects), 7u);
  bool garbage = false, cut = false, done = false;
  for (const std::string& line : log) {
    garbage |=
        line.rfind("station: robot a (Hydra, " + sink.endpoint() + "): graph ", 0) == 0 &&
        line.find(" (7 bytes): spark binary (wire, format 1.1.3): byte 0") != std::string::npos;
    cut |=
        line.find("(5000 bytes): spark binary (wire, format 1.1.3): node 0 (at byte 524): byte ") !=
            std::string::npos &&
        line.find("; left out (the next graph is taken against the last good one)") !=
            std::string::npos;
    done |= line.find("nothing for 0.5 s; taken as done") != std::string::npos;
  }
  EXPECT_TRUE(garbage);
  EXPECT_TRUE(cut);

  EXPECT_TRUE(done);
}

TEST(HydraRobots, SourcesAreNamedRobotsAtTcpEndpoints) {
  EXPECT_EQ(parseHydraRobotSource("b=tcp://127.0.0.1:8001").value().robot, kB);
  EXPECT_EQ(parseHydraRobotSource("b=tcp://127.0.0.1:8001").value().endpoint,
            "tcp://127.0.0.1:8001");
  EXPECT_EQ(parseHydraRobotSource("tcp://127.0.0.1:8001").error(),
            "'tcp://127.0.0.1:8001' is not NAME=tcp://HOST:PORT (NAME a robot letter: a, b, ...)");
  EXPECT_EQ(parseHydraRobotSource("p=tcp://127.0.0.1:8001").error(),
            "'p=tcp://127.0.0.1:8001': 'p' is not a robot letter (a-z but p: a, b, ...)");
  EXPECT_EQ(parseHydraRobotSource("a=udp://x:1").error(),
            "'a=udp://x:1': 'udp://x:1' is not tcp://HOST:PORT");
  Station station(StationOptions{});
  HydraRobotsOptions twice;
  twice.robots = {{kA, "tcp://127.0.0.1:1"}, {kA, "tcp://127.0.0.1:2"}};
  EXPECT_EQ(HydraRobots::create(station, twice).error(), "--spark-robot: robot a is given twice");
}

TEST(HydraRobots, AHelloForARobotTakenFromHydraIsRefused) {
  Station station(StationOptions{});
  StationServerOptions options;
  options.other_inputs = {kB};
  auto server = StationServer::create(station, options).value();
  std::atomic<bool> stop{false};
  std::thread serving([&] { server->serve([&] { return stop.load(); }); });
  zmq::context_t context;
  zmq::socket_t dealer(context, zmq::socket_type::dealer);
  dealer.set(zmq::sockopt::linger, 0);
  dealer.connect(server->endpoint());
  std::vector<zmq::message_t> parts;
  for (const std::string& f : encodeMessage(hello(kB, 1, kProvidesAll))) parts.emplace_back(f);
  ASSERT_TRUE(zmq::send_multipart(dealer, parts));
  std::optional<Message> answer;
  const bool answered = within(2s, [&] {
    if (answer) return true;
    std::vector<zmq::message_t> got;
    if (!zmq::recv_multipart(dealer, std::back_inserter(got), zmq::recv_flags::dontwait))
      return false;
    std::vector<std::string> frames;
    for (auto& p : got) frames.push_back(p.to_string());
    auto m = decodeMessage(frames);
    if (m && m.value().type != MessageType::kHeartbeat) answer = m.value();
    return answer.has_value();
  });
  stop = true;
  serving.join();
  ASSERT_TRUE(answered);
  EXPECT_EQ(answer->type, MessageType::kRefuse);
  EXPECT_EQ(answer->code, RefuseCode::kWrongRobot);
  EXPECT_EQ(answer->text,
            "HELLO for robot b, whose updates the station takes from another input "
            "(--spark-robot)");
  station.finish();
}

}  // namespace
}  // namespace hydra_multi::net
