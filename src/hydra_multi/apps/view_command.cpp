// `hydra-multi view DIR [--http HOST:PORT]`: serves the viewer of a finished run (the output
// folder of `run` or `station`: DIR/viewer/history.jsonl and mesh.bin) with its whole history,
// until SIGINT or SIGTERM.

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
  std::shared_ptr<web::ViewerFeed> shared = std::move(feed).value();
  const fs::path mesh_path = folder / "mesh.bin";
  if (fs::exists(mesh_path)) {
    std::ifstream in(mesh_path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    uint64_t seq = 0;
    auto checked = web::decodeViewerMesh(bytes.str(), &seq);
    if (!checked) return fail(mesh_path.string() + ": " + checked.error());
    shared->setMesh(std::make_shared<const std::string>(bytes.str()), seq);
  } else {
    std::cerr << "view: " << mesh_path.string()
              << " not found (the run did not finish?): the graph is shown without its mesh"
              << std::endl;
  }
  web::ViewerServerOptions options;
  options.http = o.http;
  options.page = o.page.empty() ? web::defaultPageFolder() : o.page;
  auto server = web::ViewerServer::start(shared, options);
  if (!server) return fail(server.error());
  std::cout << "viewer of " << o.dir << ": " << server.value()->url() << " (" << shared->latest()
            << " backend rounds" << (shared->ended() ? "" : ", the run did not finish")
            << "; Ctrl-C stops it)" << std::endl;
  const StopSignals signals;
  while (!StopSignals::requested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!o.quiet) std::cerr << "view: stopped" << std::endl;
  return 0;
}

}  // namespace hydra_multi::apps
