#include "hydra_multi/web/viewer_server.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>

#include "hydra_multi/web/viewer_mesh.h"
#include "web/round_fixture.h"

namespace hydra_multi::web {
namespace {

using nlohmann::json;
using testing::RoundFixture;

// A page folder with a stand-in index.html (the real page is tested in a browser: tests/web/*.mjs).
class ViewerServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    page_ = std::filesystem::temp_directory_path() / ("hm_page_" + std::to_string(::getpid()));
    std::filesystem::create_directories(page_);
    std::ofstream(page_ / "index.html") << "<!doctype html><title>viewer</title>";
    feed_ = std::make_shared<ViewerFeed>();
  }
  void TearDown() override { std::filesystem::remove_all(page_); }

  std::unique_ptr<ViewerServer> start(ViewerServerOptions options = {}) {
    options.http = "127.0.0.1:0";
    options.page = page_.string();
    auto server = ViewerServer::start(feed_, options);
    EXPECT_TRUE(server) << server.error();
    return std::move(server).value();
  }
  void publishRound(size_t round) {
    RoundFixture f(7);
    f.timing.round = round;
    f.graph.addOrUpdateNode(makeNode(NodeId('O', 500 + round), Layer::kObjects, {1, 1, 1}));
    feed_->publish(viewOfRound(f.output()));
  }
  static httplib::Client client(const ViewerServer& server) {
    const std::string url = server.url();  // http://127.0.0.1:PORT/
    httplib::Client c(url.substr(0, url.size() - 1));
    c.set_read_timeout(5, 0);
    c.set_connection_timeout(2, 0);
    return c;
  }
  // The events of one stream, read until the server ends it (after "end").
  static std::vector<std::pair<std::string, std::string>> events(const ViewerServer& server,
                                                                 const std::string& last_id) {
    httplib::Client c = client(server);
    httplib::Headers headers;
    if (!last_id.empty()) headers.emplace("Last-Event-ID", last_id);
    std::string body;
    auto res = c.Get("/api/events", headers, [&](const char* data, size_t n) {
      body.append(data, n);
      return body.size() < (64u << 20);
    });
    EXPECT_TRUE(res) << "the stream did not end by itself";
    std::vector<std::pair<std::string, std::string>> out;  // (type, id)
    std::istringstream in(body);
    std::string line, type, id;
    while (std::getline(in, line)) {
      if (line.rfind("event: ", 0) == 0) type = line.substr(7);
      if (line.rfind("id: ", 0) == 0) id = line.substr(4);
      if (line.empty() && !type.empty()) {
        out.emplace_back(type, id);
        type.clear();
        id.clear();
      }
    }
    return out;
  }

  std::filesystem::path page_;
  std::shared_ptr<ViewerFeed> feed_;
};

TEST_F(ViewerServerTest, ServesThePageTheRoundsTheViewsAndTheMesh) {
  publishRound(0);
  publishRound(1);
  RoundFixture f(7);
  feed_->setMesh(std::make_shared<const std::string>(encodeViewerMesh(f.graph.mesh(), 2)), 2);
  const auto server = start();
  httplib::Client c = client(*server);
  // The answer to GET path, which must have the status.
  const auto get = [&c](const std::string& path, int status) {
    httplib::Result res = c.Get(path);
    EXPECT_TRUE(res) << path;
    EXPECT_EQ(res ? res->status : 0, status) << path;
    return res ? res->body : std::string();
  };
  EXPECT_NE(get("/", 200).find("viewer"), std::string::npos);
  EXPECT_EQ(json::parse(get("/api/rounds", 200))["rounds"].size(), 2u);
  EXPECT_EQ(json::parse(get("/api/view?seq=1", 200))["round"], 0);
  EXPECT_NE(get("/api/view?seq=9", 404).find("no view 9"), std::string::npos);
  get("/api/view?seq=x", 400);
  EXPECT_TRUE(decodeViewerMesh(get("/api/mesh", 200)));
  auto mesh = c.Get("/api/mesh");
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->get_header_value("X-Mesh-Seq"), "2");
  get("/api/mesh?after=2", 204);
  get("/api/mesh?after=1", 200);
}

TEST_F(ViewerServerTest, StreamGivesASnapshotThenDeltasThenTheEnd) {
  publishRound(0);
  publishRound(1);
  const auto server = start();
  std::thread later([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    publishRound(2);
    feed_->finish();
  });
  const auto got = events(*server, "");
  later.join();
  const std::string e = feed_->epoch();
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"snapshot", e + "-2"}, {"delta", e + "-3"}, {"delta", e + "-4"}, {"end", ""}};
  EXPECT_EQ(got, expected);
}

TEST_F(ViewerServerTest, ReconnectingViewerResumesOrTakesANewSnapshot) {
  for (size_t r = 0; r < 4; ++r) publishRound(r);
  feed_->finish();  // 5 views
  const auto server = start();
  const std::string e = feed_->epoch();
  const auto resumed = events(*server, e + "-2");
  const std::vector<std::pair<std::string, std::string>> after2 = {
      {"delta", e + "-3"}, {"delta", e + "-4"}, {"delta", e + "-5"}, {"end", ""}};
  EXPECT_EQ(resumed, after2);
  // Another feed's numbers (a restarted station), a number ahead, or garbage: a new snapshot.
  for (const std::string& last : {std::string("0123abcd-2"), e + "-99", std::string("nonsense")}) {
    const auto fresh = events(*server, last);
    const std::vector<std::pair<std::string, std::string>> snapshot = {{"snapshot", e + "-5"},
                                                                       {"end", ""}};
    EXPECT_EQ(fresh, snapshot) << last;
  }
  EXPECT_EQ(server->streamsServed(), 4u);
}

TEST_F(ViewerServerTest, StatusEventsCarryTheLinks) {
  publishRound(0);
  ViewerServerOptions options;
  options.links = [] { return std::map<RobotId, RobotLink>{{RobotId(1), {true, 0.5, 1234}}}; };
  const auto server = start(options);
  std::thread later([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1300));
    feed_->finish();
  });
  const auto got = events(*server, "");
  later.join();
  size_t status = 0;
  for (const auto& [type, id] : got) status += type == "status";
  EXPECT_GE(status, 1u);
}

TEST_F(ViewerServerTest, RefusesBadAddressesAndAMissingPage) {
  for (const char* http : {"127.0.0.1", "127.0.0.1:70000", "127.0.0.1:x", ":80"}) {
    ViewerServerOptions o;
    o.http = http;
    o.page = page_.string();
    auto server = ViewerServer::start(feed_, o);
    ASSERT_FALSE(server) << http;
    EXPECT_NE(server.error().find(http), std::string::npos) << server.error();
  }
  ViewerServerOptions o;
  o.http = "127.0.0.1:0";
  o.page = (page_ / "nothing").string();
  auto server = ViewerServer::start(feed_, o);
  ASSERT_FALSE(server);
  EXPECT_NE(server.error().find("not built"), std::string::npos) << server.error();
  // A port in use.
  const auto first = start();
  const std::string port = first->url().substr(first->url().rfind(':') + 1);
  o.page = page_.string();
  o.http = "127.0.0.1:" + port.substr(0, port.size() - 1);
  auto taken = ViewerServer::start(feed_, o);
  ASSERT_FALSE(taken);
  EXPECT_NE(taken.error().find("cannot listen"), std::string::npos) << taken.error();
}

}  // namespace
}  // namespace hydra_multi::web
