// `hydra-multi view DIR [--http HOST:PORT] [--replay S]`: serves the viewer of a finished run (the
// output folder of `run` or `station`: DIR/viewer/history.jsonl and mesh.bin) with its whole
// history, until SIGINT or SIGTERM. With --replay the history is published again as if live, one
// view every S seconds, to a feed of its own (a new epoch), with the final mesh from the start.

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/stop_signals.h"
#include "hydra_multi/web/viewer_mesh.h"
#include "hydra_multi/web/viewer_server.h"

namespace hydra_multi::apps {

int runView(const ViewOptions& o) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(o.dir) / "viewer";
  const fs::path history = folder / "history.jsonl";
  if (!fs::exists(history))
    return fail(history.string() +
                " not found: DIR must be the output folder of `run` or `station`");
  auto feed = web::ViewerFeed::load(history.string());
  if (!feed) return fail(feed.error());
  std::shared_ptr<web::ViewerFeed> history_feed = std::move(feed).value();
  std::shared_ptr<web::ViewerFeed> shared =
      o.replay_s > 0 ? std::make_shared<web::ViewerFeed>() : history_feed;
  const fs::path mesh_path = folder / "mesh.bin";
  if (fs::exists(mesh_path)) {
    std::ifstream in(mesh_path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    uint64_t seq = 0;
    auto checked = web::decodeViewerMesh(bytes.str(), &seq);
    if (!checked) return fail(mesh_path.string() + ": " + checked.error());
    history_feed->setMesh(std::make_shared<const std::string>(bytes.str()), seq);
    if (shared != history_feed) shared->setMesh(history_feed->mesh(), 1);
  } else {
    std::cerr << "view: " << mesh_path.string()
              << " not found (the run did not finish?): the graph is shown without its mesh"
              << std::endl;
  }
  web::ViewerServerOptions options;
  options.http = o.http;
  options.page = o.page.empty() ? web::defaultPageFolder() : o.page;
  if (!o.quiet) options.log = [](const std::string& line) { std::cerr << line << std::endl; };
  auto server = web::ViewerServer::start(shared, options);
  if (!server) return fail(server.error());
  const uint64_t views = history_feed->latest();
  std::cout << "viewer of " << o.dir << ": " << server.value()->url() << " (" << views
            << " views of backend rounds"
            << (history_feed->ended() ? "" : ", the run did not finish")
            << (o.replay_s > 0 ? ", replayed one every " + std::to_string(o.replay_s) + " s" : "")
            << "; Ctrl-C stops it)" << std::endl;
  const StopSignals signals;
  auto next = std::chrono::steady_clock::now();
  for (uint64_t seq = 1; o.replay_s > 0 && seq <= views && !StopSignals::requested();) {
    if (std::chrono::steady_clock::now() < next) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    web::ViewState view;
    if (Status s = web::applyViewDelta(view, nlohmann::json::parse(*history_feed->snapshot(seq)));
        !s)
      return fail(history.string() + ": view " + std::to_string(seq) + ": " + s.message());
    shared->publish(std::move(view));
    if (!o.quiet) std::cerr << "view: replayed view " << seq << " of " << views << std::endl;
    ++seq;
    next += std::chrono::milliseconds(static_cast<int64_t>(o.replay_s * 1000));
  }
  if (o.replay_s > 0) shared->finish();
  while (!StopSignals::requested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!o.quiet) std::cerr << "view: stopped" << std::endl;
  return 0;
}

}  // namespace hydra_multi::apps
