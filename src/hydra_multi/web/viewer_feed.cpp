#include "hydra_multi/web/viewer_feed.h"

#include <algorithm>
#include <cstdio>
#include <random>

namespace hydra_multi::web {
namespace {

using nlohmann::json;

constexpr const char* kHistoryFormat = "hydra-multi viewer history";

std::string randomEpoch() {
  std::random_device device;
  char text[17];
  std::snprintf(text, sizeof(text), "%08x%08x", device(), device());
  return text;
}

json summaryOf(const json& delta) {
  return {{"seq", delta["seq"]},
          {"round", delta["round"]},
          {"final", delta["final"]},
          {"info", delta["info"]},
          {"robots", delta["robots"]}};
}

}  // namespace

ViewerFeed::ViewerFeed(std::string history_path, std::string epoch)
    : epoch_(epoch.empty() ? randomEpoch() : std::move(epoch)) {
  if (!history_path.empty()) {
    history_.open(history_path, std::ios::trunc);
    history_ << json{{"format", kHistoryFormat}, {"version", 1}, {"epoch", epoch_}}.dump() << "\n";
    history_.flush();
  }
}

Result<std::unique_ptr<ViewerFeed>> ViewerFeed::load(const std::string& history_path) {
  std::ifstream in(history_path);
  if (!in) return Error{history_path + ": cannot be read"};
  std::string line;
  size_t number = 1;
  const auto fail = [&](const std::string& what) {
    return Error{history_path + " line " + std::to_string(number) + ": " + what};
  };
  if (!std::getline(in, line)) return fail("empty: no header line");
  json header = json::parse(line, nullptr, false);
  if (header.is_discarded() || !header.is_object() || header.value("format", "") != kHistoryFormat)
    return fail("not a viewer history (its header is not {\"format\": \"" +
                std::string(kHistoryFormat) + "\", ...})");
  if (header.value("version", 0) != 1)
    return fail("version " + header["version"].dump() + " is not 1, the one this build reads");
  if (!header["epoch"].is_string()) return fail("the header has no epoch");
  auto feed = std::make_unique<ViewerFeed>(std::string(), header["epoch"].get<std::string>());
  ViewState state;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    json delta = json::parse(line, nullptr, false);
    if (delta.is_discarded()) return fail("not JSON (a line cut short by a crash?)");
    ViewState next = state;
    if (const Status applied = applyViewDelta(next, delta); !applied)
      return fail(applied.message());
    if (next.seq != feed->latest() + 1)
      return fail("sequence " + std::to_string(next.seq) + " after " +
                  std::to_string(feed->latest()));
    state = next;
    std::lock_guard<std::mutex> lock(feed->mutex_);
    feed->append(delta, std::move(next));
  }
  std::lock_guard<std::mutex> lock(feed->mutex_);
  feed->ended_ = feed->latest_.final;
  return feed;
}

void ViewerFeed::append(const json& delta, ViewState next) {
  std::string text = delta.dump();
  delta_bytes_ += text.size();
  since_checkpoint_ += text.size();
  summaries_.push_back(summaryOf(delta));
  latest_ = std::move(next);
  // A checkpoint when the deltas since the last outweigh the last whole view: replaying from one
  // then costs at most about that much again.
  if (checkpoints_.empty() || since_checkpoint_ >= checkpoints_.back().second.size()) {
    checkpoints_.emplace_back(latest_.seq, snapshotOfView(latest_).dump());
    since_checkpoint_ = 0;
  }
  if (history_.is_open()) {
    history_ << text << "\n";
    history_.flush();
  }
  deltas_.push_back(std::move(text));
}

void ViewerFeed::publish(ViewState view) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    view.seq = deltas_.size() + 1;
    view.info["published_unix_ms"] = std::chrono::duration_cast<std::chrono::milliseconds>(
                                         std::chrono::system_clock::now().time_since_epoch())
                                         .count();
    const json delta = diffViews(latest_, view);
    append(delta, std::move(view));
  }
  newer_.notify_all();
}

void ViewerFeed::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (ended_) return;
    ended_ = true;
    if (!deltas_.empty() && !latest_.final) {
      ViewState last = latest_;
      last.final = true;
      last.seq = deltas_.size() + 1;
      const json delta = diffViews(latest_, last);
      append(delta, std::move(last));
    }
  }
  newer_.notify_all();
}

void ViewerFeed::setMesh(std::shared_ptr<const std::string> encoded, uint64_t seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  mesh_ = std::move(encoded);
  mesh_seq_ = seq;
}

std::shared_ptr<const std::string> ViewerFeed::mesh() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return mesh_;
}

uint64_t ViewerFeed::meshSequence() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return mesh_seq_;
}

uint64_t ViewerFeed::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return deltas_.size();
}

bool ViewerFeed::ended() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ended_;
}

ViewState ViewerFeed::viewAt(uint64_t seq) const {
  if (seq == latest_.seq) return latest_;
  // The last checkpoint at or before seq, then the deltas after it.
  auto it = std::upper_bound(checkpoints_.begin(), checkpoints_.end(), seq,
                             [](uint64_t s, const auto& c) { return s < c.first; });
  --it;  // the first checkpoint is view 1
  ViewState view;
  Status ok = applyViewDelta(view, json::parse(it->second));
  for (uint64_t s = it->first + 1; ok && s <= seq; ++s)
    ok = applyViewDelta(view, json::parse(deltas_[s - 1]));
  if (!ok) throw std::logic_error("viewer feed: its own history does not apply: " + ok.message());
  return view;
}

std::optional<std::string> ViewerFeed::snapshot(uint64_t seq) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (deltas_.empty()) return std::nullopt;
  if (seq == 0) seq = deltas_.size();
  if (seq > deltas_.size()) return std::nullopt;
  if (cached_.first == seq && !cached_.second.empty()) return cached_.second;
  std::string text = snapshotOfView(viewAt(seq)).dump();
  cached_ = {seq, text};
  return text;
}

std::vector<std::string> ViewerFeed::deltasAfter(uint64_t seq) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (seq >= deltas_.size()) return {};
  return {deltas_.begin() + static_cast<std::ptrdiff_t>(seq), deltas_.end()};
}

std::string ViewerFeed::roundsJson() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return json{{"epoch", epoch_}, {"ended", ended_}, {"rounds", summaries_}}.dump();
}

bool ViewerFeed::waitNewer(uint64_t seq, std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  newer_.wait_for(lock, timeout, [&] { return deltas_.size() > seq || ended_; });
  return deltas_.size() > seq;
}

size_t ViewerFeed::deltaBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return delta_bytes_;
}

size_t ViewerFeed::checkpoints() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return checkpoints_.size();
}

}  // namespace hydra_multi::web
