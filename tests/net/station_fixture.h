#pragma once
// What the station-server tests share: the tiny team's streams, a station serving in a thread on
// loopback, a robot client's options for tests (short backoffs and heartbeats), and a raw
// connection that sends any frames and reads the station's answers.

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/net/protocol.h"
#include "hydra_multi/net/robot_client.h"
#include "hydra_multi/net/station_server.h"
#include "hydra_multi/sim/dataset.h"

namespace hydra_multi::net::test_support {

using namespace std::chrono_literals;

inline const sim::SimulatedDataset& tiny() {
  static const sim::SimulatedDataset dataset =
      sim::simulateDataset(sim::presetConfig("tiny", 1).value()).value();
  return dataset;
}

// A station and its server, serving in a thread until stop() or the expected BYEs.
class Served {
 public:
  explicit Served(size_t expect_robots, StationServerOptions options = {})
      : station_(StationOptions{}) {
    options.log = [this](const std::string& line) {
      std::lock_guard<std::mutex> lock(mutex_);
      log_.push_back(line);
    };
    server_ = StationServer::create(station_, options).value();
    thread_ = std::thread([this, expect_robots] {
      server_->serve([this] { return stop_.load(); }, expect_robots);
      finished_ = true;
    });
  }
  ~Served() { stop(); }
  const std::string& endpoint() const { return server_->endpoint(); }
  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  // Waits for the serving thread to end by itself (the expected BYEs), at most `timeout`.
  bool ended(std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(10ms);
    return done();
  }
  StationResult finish() {
    stop();
    return station_.finish();
  }
  const StationServerCounts& counts() const { return server_->counts(); }
  std::vector<std::string> log() {
    std::lock_guard<std::mutex> lock(mutex_);
    return log_;
  }

 private:
  bool done() {
    // serve() returned: the thread is ready to join.
    if (!thread_.joinable()) return true;
    if (!finished_.load()) return false;
    thread_.join();
    return true;
  }
  Station station_;
  std::unique_ptr<StationServer> server_;
  std::atomic<bool> stop_{false}, finished_{false};
  std::thread thread_;
  std::mutex mutex_;
  std::vector<std::string> log_;
};

// Sends robot `r`'s whole stream and says BYE; false if it could not within `timeout`.
inline bool sendStream(RobotClient& client, size_t r, std::chrono::milliseconds timeout = 10s) {
  for (const RobotUpdate& u : tiny().streams[r]) {
    while (!client.enqueue(u)) client.pump(10ms);
    client.pump(0ms);
  }
  return client.finish(timeout);
}

inline RobotClientOptions clientOptions(const std::string& endpoint) {
  RobotClientOptions options;
  options.connect = endpoint;
  options.backoff_min_s = 0.05;
  options.backoff_max_s = 0.2;
  options.heartbeat_s = 0.2;
  return options;
}

// A raw connection's messages, and the station's answers.
class RawPeer {
 public:
  explicit RawPeer(const std::string& endpoint) : socket_(context_, zmq::socket_type::dealer) {
    socket_.set(zmq::sockopt::linger, 0);
    socket_.connect(endpoint);
  }
  void send(const std::vector<std::string>& frames) {
    std::vector<zmq::message_t> parts;
    for (const std::string& f : frames) parts.emplace_back(f.data(), f.size());
    ASSERT_TRUE(zmq::send_multipart(socket_, parts));
  }
  // The next message that is not a heartbeat, within 2 s.
  Message next() {
    const auto end = std::chrono::steady_clock::now() + 2s;
    while (std::chrono::steady_clock::now() < end) {
      zmq::pollitem_t items[] = {{socket_.handle(), 0, ZMQ_POLLIN, 0}};
      zmq::poll(items, 1, 50ms);
      std::vector<zmq::message_t> parts;
      if (!zmq::recv_multipart(socket_, std::back_inserter(parts), zmq::recv_flags::dontwait))
        continue;
      std::vector<std::string> frames;
      for (auto& p : parts) frames.push_back(p.to_string());
      auto m = decodeMessage(frames);
      if (m && m.value().type != MessageType::kHeartbeat) return m.value();
    }
    ADD_FAILURE() << "no answer from the station";
    return Message{};
  }

 private:
  zmq::context_t context_;
  zmq::socket_t socket_;
};

inline std::string payloadOf(size_t robot, size_t index) {
  return io::encodeRobotUpdateBinary(tiny().streams[robot][index]);
}

}  // namespace hydra_multi::net::test_support
