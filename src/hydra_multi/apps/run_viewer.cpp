#include "hydra_multi/apps/run_viewer.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "hydra_multi/web/viewer_mesh.h"

namespace hydra_multi::apps {

namespace fs = std::filesystem;

Result<std::unique_ptr<RunViewer>> RunViewer::open(const std::string& out, const std::string& http,
                                                   Links links, bool quiet) {
  std::error_code error;
  const fs::path folder = fs::path(out) / "viewer";
  fs::create_directories(folder, error);
  if (error) return Error{"cannot create " + folder.string() + ": " + error.message()};
  auto viewer = std::make_unique<RunViewer>();
  viewer->out_ = out;
  viewer->links_ = std::move(links);
  viewer->feed_ = std::make_shared<web::ViewerFeed>((folder / "history.jsonl").string());
  if (!http.empty()) {
    web::ViewerServerOptions options;
    options.http = http;
    options.page = web::defaultPageFolder();
    if (viewer->links_) {
      RunViewer* v = viewer.get();
      options.links = [v] {
        std::map<RobotId, web::RobotLink> links = v->links_(nullptr);
        if (!links.empty()) return links;
        std::lock_guard<std::mutex> lock(v->links_mutex_);
        return v->last_links_;
      };
    }
    if (!quiet) options.log = [](const std::string& line) { std::cerr << line << std::endl; };
    auto server = web::ViewerServer::start(viewer->feed_, options);
    if (!server) return Error{server.error()};
    viewer->server_ = std::move(server).value();
  }
  return viewer;
}

void RunViewer::onRound(const RoundOutput& round) {
  // The round's end, so that the lag to the page can be told from it (info.round_end_unix_ms).
  const int64_t end_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
  std::map<RobotId, web::RobotLink> links;
  if (links_) {
    links = links_(&round);
    std::lock_guard<std::mutex> lock(links_mutex_);
    last_links_ = links;
  }
  web::ViewState view = web::viewOfRound(round, links);
  view.info["round_end_unix_ms"] = end_ms;
  feed_->publish(std::move(view));
  const auto now = std::chrono::steady_clock::now();
  if (server_ && now - last_mesh_ >= std::chrono::seconds(1)) {
    last_mesh_ = now;
    feed_->setMesh(std::make_shared<const std::string>(
                       web::encodeViewerMesh(round.graph.mesh(), feed_->latest())),
                   feed_->latest());
  }
}

Status RunViewer::finish(const SceneGraph& graph) {
  feed_->finish();
  auto mesh =
      std::make_shared<const std::string>(web::encodeViewerMesh(graph.mesh(), feed_->latest()));
  feed_->setMesh(mesh, feed_->latest());
  const fs::path path = fs::path(out_) / "viewer" / "mesh.bin";
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(mesh->data(), static_cast<std::streamsize>(mesh->size()));
  if (!file) return Error{"cannot write " + path.string()};
  // Open streams take the final view and the end within their next pass (250 ms).
  if (server_ && server_->streamsServed() > 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
  return Status::Ok();
}

std::string RunViewer::url() const { return server_ ? server_->url() : std::string(); }

}  // namespace hydra_multi::apps
