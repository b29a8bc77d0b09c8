#pragma once
// ViewerFeed: the viewer's history of a run, one view per backend round (view_state.h), numbered
// by a sequence that starts at 1 and kept as deltas, with a whole view (a checkpoint) whenever the
// deltas since the last one outweigh it, so that the view of any round costs at most about two
// views' worth of work. The feed's epoch (random per run) tells a viewer that reconnects whether
// the numbers it holds are this feed's. With a history file, every delta is appended to it as one
// JSON line as it is published, after a header line; `view DIR` reads it back (load()). The mesh
// is kept apart (viewer_mesh.h): the latest one, by its sequence. All methods are thread-safe.

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/web/view_state.h"

namespace hydra_multi::web {

class ViewerFeed {
 public:
  /// `history_path`: the file the deltas are appended to (empty: none). `epoch`: the feed's (empty:
  /// a random one).
  explicit ViewerFeed(std::string history_path = {}, std::string epoch = {});
  /// Reads a history file back, with its epoch; an error names the file and line.
  static Result<std::unique_ptr<ViewerFeed>> load(const std::string& history_path);

  /// Publishes a round's view with the next sequence (its seq, and info.published_unix_ms, the
  /// wall clock's time, are set here).
  void publish(ViewState view);
  /// Marks the latest view final (the run is over); publishes nothing when there is none.
  void finish();
  /// The latest mesh (encoded, viewer_mesh.h), with the sequence of the view it belongs to.
  void setMesh(std::shared_ptr<const std::string> encoded, uint64_t seq);
  std::shared_ptr<const std::string> mesh() const;
  uint64_t meshSequence() const;

  const std::string& epoch() const { return epoch_; }
  uint64_t latest() const;  ///< 0: nothing yet
  bool ended() const;
  /// The snapshot (snapshotOfView's JSON text) of view `seq` (1..latest), of the latest when 0;
  /// nullopt when there is no such view.
  std::optional<std::string> snapshot(uint64_t seq = 0) const;
  /// The deltas after `seq` up to the latest, as JSON texts (empty when `seq` is the latest).
  std::vector<std::string> deltasAfter(uint64_t seq) const;
  /// Per view: {seq, round, final, info, robots} (for the time axis and the charts).
  std::string roundsJson() const;
  /// Waits until a view after `seq` is published, the feed ended, or `timeout`; true if newer.
  bool waitNewer(uint64_t seq, std::chrono::milliseconds timeout) const;
  /// Bytes of the deltas held, of the checkpoints, and the checkpoints' count.
  size_t deltaBytes() const;
  size_t checkpoints() const;

 private:
  void append(const nlohmann::json& delta, ViewState next);
  ViewState viewAt(uint64_t seq) const;  // under mutex_

  const std::string epoch_;
  mutable std::mutex mutex_;
  mutable std::condition_variable newer_;
  std::ofstream history_;
  std::vector<std::string> deltas_;  // deltas_[seq - 1]
  std::vector<nlohmann::json> summaries_;
  std::vector<std::pair<uint64_t, std::string>> checkpoints_;  // (seq, snapshot text), ascending
  size_t since_checkpoint_ = 0;                                // delta bytes
  size_t delta_bytes_ = 0;
  ViewState latest_;
  bool ended_ = false;
  std::shared_ptr<const std::string> mesh_;
  uint64_t mesh_seq_ = 0;
  mutable std::pair<uint64_t, std::string> cached_;  // the last snapshot asked for
};

}  // namespace hydra_multi::web
