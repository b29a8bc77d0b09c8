#pragma once
// The viewer's side of `run` and `station` (docs/VIEWER.md): every backend round's view appended
// to OUT/viewer/history.jsonl as it comes, the final mesh as OUT/viewer/mesh.bin, so that `view
// OUT` shows the run with its whole history; with --http also the viewer server, live, with the
// latest mesh at most once a second.

#include <chrono>
#include <memory>
#include <mutex>
#include <string>

#include "hydra_multi/web/viewer_server.h"

namespace hydra_multi::apps {

class RunViewer {
 public:
  /// The robots' links at a round (the round is that of the view being made; nullptr for the
  /// server's status events in between).
  using Links = std::function<std::map<RobotId, web::RobotLink>(const RoundOutput* round)>;
  /// `http`: HOST:PORT to serve on (empty: no server). An error: the folder cannot be written,
  /// the address is bad or taken, or the page is not built.
  static Result<std::unique_ptr<RunViewer>> open(const std::string& out, const std::string& http,
                                                 Links links, bool quiet);
  /// A backend round (the station's backend thread): its view, stamped with the round's end
  /// (info.round_end_unix_ms) before it is built.
  void onRound(const RoundOutput& round);
  /// The run is over: the final view and its mesh (OUT/viewer/mesh.bin).
  Status finish(const SceneGraph& graph);
  /// The server's address ("" without one).
  std::string url() const;
  const web::ViewerFeed& feed() const { return *feed_; }

 private:
  std::string out_;
  Links links_;
  std::shared_ptr<web::ViewerFeed> feed_;
  std::unique_ptr<web::ViewerServer> server_;
  std::chrono::steady_clock::time_point last_mesh_{};
  std::mutex links_mutex_;
  std::map<RobotId, web::RobotLink> last_links_;  // of the last round, for status events
};

}  // namespace hydra_multi::apps
