#pragma once
// The viewer's HTTP server (docs/VIEWER.md "Server"): the built page (web/page, vite's output) as
// static files, and a feed (viewer_feed.h) as
//   GET /api/rounds        every view's figures, for the time axis and the charts;
//   GET /api/view?seq=N    the snapshot of view N (the latest without seq);
//   GET /api/mesh[?after=S] the latest mesh (viewer_mesh.h), its view in the X-Mesh-Seq header
//                          (204 when it is not newer than view S);
//   GET /api/events        Server-Sent Events: a "snapshot", then a "delta" per view, each with
//                          the id "EPOCH-SEQ"; a viewer that reconnects with Last-Event-ID (or
//                          ?last=EPOCH-SEQ) of this feed gets the deltas it missed, any other a
//                          new snapshot; "status" events carry the robots' links every second
//                          (live only), "end" follows the final view.
// cpp-httplib (Debian's libcpp-httplib-dev; plain HTTP, no TLS): one thread per open stream.

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/web/viewer_feed.h"

namespace hydra_multi::web {

struct ViewerServerOptions {
  std::string http = "127.0.0.1:7880";  ///< HOST:PORT; port 0 takes a free one
  std::string page;                     ///< the built page's folder (index.html)
  /// The robots' links now, for "status" events (empty: none are sent).
  std::function<std::map<RobotId, RobotLink>()> links;
  std::function<void(const std::string&)> log;
};

/// The folder of the page built beside this executable (BUILD/web), or "" when there is none.
std::string defaultPageFolder();

class ViewerServer {
 public:
  /// Binds and starts serving; an error when HOST:PORT is malformed or cannot be bound, or the
  /// page folder has no index.html.
  static Result<std::unique_ptr<ViewerServer>> start(std::shared_ptr<ViewerFeed> feed,
                                                     ViewerServerOptions options);
  ~ViewerServer();                 ///< stops: open streams end within half a second
  const std::string& url() const;  ///< "http://HOST:PORT/"
  size_t streamsServed() const;    ///< event streams opened so far

 private:
  struct Impl;
  explicit ViewerServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::web
