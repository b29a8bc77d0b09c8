#include "hydra_multi/frontend/loop_closure_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "hydra_multi/core/best_accepted.h"

namespace hydra_multi {
namespace {

constexpr size_t kMaxObjectPairs = 200;
constexpr size_t kMaxPairsPerWord = 4;

// The upper median of a non-empty list.
template <typename T>
T median(std::vector<T> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace

const char* loopClosureSourceName(DetectedLoopClosure::Source source) {
  return source == DetectedLoopClosure::Source::kObjects ? "objects" : "visual";
}

std::vector<double> interRobotSupport(const std::vector<DetectedLoopClosure>& closures) {
  std::map<DetectedLoopClosure::Source, std::vector<double>> per_inlier;
  for (const DetectedLoopClosure& c : closures) {
    if (c.interRobot() && c.inliers > 0)
      per_inlier[c.source].push_back(c.distinctiveness / double(c.inliers));
  }
  std::map<DetectedLoopClosure::Source, double> typical;
  for (const auto& [source, values] : per_inlier) typical[source] = median(values);
  std::vector<double> support;
  for (const DetectedLoopClosure& c : closures) {
    if (!c.interRobot()) continue;
    support.push_back(std::max(0.0, c.distinctiveness - typical[c.source] * double(c.inliers)));
  }
  return support;
}

LoopClosureDetector::LoopClosureDetector(LoopClosureOptions options) : options_(options) {}

std::vector<DetectedLoopClosure> LoopClosureDetector::update(
    const SceneGraphProcessor& processor, const std::vector<NodeId>& new_keyframes) {
  pending_.insert(pending_.end(), new_keyframes.begin(), new_keyframes.end());
  return run(processor, false);
}

std::vector<DetectedLoopClosure> LoopClosureDetector::flush(const SceneGraphProcessor& processor) {
  return run(processor, true);
}

std::vector<DetectedLoopClosure> LoopClosureDetector::run(const SceneGraphProcessor& processor,
                                                          bool all) {
  std::vector<DetectedLoopClosure> found;
  const SceneGraph& graph = processor.graph();
  std::vector<NodeId> later;
  for (const NodeId id : pending_) {
    const Node* node = graph.findNode(id);
    const auto robot = id.sourceRobot();
    if (node == nullptr || !robot) continue;  // removed again (a snapshot replaced it)
    const RobotFrontendState* state = processor.robot(*robot);
    const int64_t time = node->find<AgentAttributes>()->timestamp_ns;
    if (!all && state != nullptr &&
        time > state->last_time_ns - static_cast<int64_t>(options_.descriptor_delay_s * 1e9)) {
      later.push_back(id);
      continue;
    }
    const KeyframeDescriptor* visual = nullptr;
    if (state != nullptr) {
      const auto it = state->descriptors.find(id);
      if (it != state->descriptors.end()) visual = &it->second;
    }
    Entry entry;
    entry.robot = *robot;
    entry.time_ns = time;
    entry.d = describeKeyframe(graph, id, visual, options_.descriptors);
    entry.place_bins.assign(static_cast<size_t>(std::max(0, options_.descriptors.place_bins)), 0.0);
    for (const auto& [bin, weight] : entry.d.place_radii) {
      if (bin < entry.place_bins.size()) entry.place_bins[bin] = weight;
    }
    if (auto closure = match(processor, entry)) {
      found.push_back(*closure);
      found_.push_back(*closure);
    }
    if (visual != nullptr) {
      std::set<uint32_t> words;
      for (const BowEntry& b : visual->bow) words.insert(b.word);
      for (const uint32_t w : words) ++word_keyframes_[w];
    }
    const auto index = static_cast<uint32_t>(described_.size());
    for (const auto& [word, weight] : entry.d.bow) word_postings_[word].emplace_back(index, weight);
    for (const auto& [label, weight] : entry.d.object_labels)
      label_postings_[label].emplace_back(index, weight);
    described_.push_back(std::move(entry));
  }
  pending_ = std::move(later);
  return found;
}

std::optional<DetectedLoopClosure> LoopClosureDetector::match(const SceneGraphProcessor& processor,
                                                              const Entry& query) {
  if (!query.d.root) return std::nullopt;
  const int64_t separation = static_cast<int64_t>(options_.min_time_separation_s * 1e9);
  // Objects' and bag-of-words scores through the labels' and words' postings: the sum of the
  // bin-wise minima, over the shared bins in increasing order, as histogramScore adds them.
  const auto scores = [this](const Histogram& query_bins, const auto& postings_of) {
    std::vector<double> score;
    if (query_bins.empty()) return score;
    score.assign(described_.size(), 0.0);
    for (const auto& [bin, weight] : query_bins) {
      const auto postings = postings_of.find(bin);
      if (postings == postings_of.end()) continue;
      for (const auto& [k, w] : postings->second) score[k] += std::min(weight, w);
    }
    return score;
  };
  // Whether a described keyframe may close a loop with the query: rooted, and of another robot
  // (or of its own, long enough apart).
  const auto eligible = [&](size_t k) {
    const Entry& candidate = described_[k];
    return candidate.d.root && (candidate.robot != query.robot ||
                                (options_.detect_intra_robot &&
                                 std::llabs(query.time_ns - candidate.time_ns) >= separation));
  };
  // Whether its places are alike the query's (top-down: the places prune).
  const auto alike = [&](size_t k) {
    const Entry& candidate = described_[k];
    // The places' score over every bin (a bin in neither adds exactly 0).
    double place_score = 0.0;
    const size_t bins = std::min(query.place_bins.size(), candidate.place_bins.size());
    for (size_t b = 0; b < bins; ++b)
      place_score += std::min(query.place_bins[b], candidate.place_bins[b]);
    return place_score >= options_.place_min_score;
  };
  const auto plausible = [&](const DetectedLoopClosure& c) {
    return c.T_a_b.translation().norm() <= options_.max_keyframe_distance;
  };
  // Bottom-up: objects first, then visual keypoints. The objects' best eligible keyframe with
  // places alike (ties: the earlier one), comparing places only down to it.
  const std::vector<double> object_score = scores(query.d.object_labels, label_postings_);
  const auto best = bestAccepted(
      object_score,
      [&](size_t k) {
        return object_score[k] >= options_.object_min_score && object_score[k] > 0.0 &&
               !described_[k].d.object_labels.empty() && eligible(k);
      },
      alike);
  if (best && object_score[*best] >= options_.object_register_score) {
    auto closure = verifyObjects(processor, query, described_[*best]);
    if (closure && plausible(*closure)) {
      closure->score = object_score[*best];
      return closure;
    }
  }
  const std::vector<double> bow_score = scores(query.d.bow, word_postings_);
  std::vector<std::pair<double, size_t>> visual;
  for (size_t k = 0; k < bow_score.size(); ++k) {
    if (bow_score[k] >= options_.bow_min_score && !described_[k].d.bow.empty() && eligible(k) &&
        alike(k))
      visual.emplace_back(bow_score[k], k);
  }
  std::sort(visual.begin(), visual.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  for (size_t i = 0; i < visual.size() && i < options_.visual_candidates; ++i) {
    auto closure = verifyVisual(processor, query, described_[visual[i].second]);
    if (closure && plausible(*closure)) {
      closure->score = visual[i].first;
      return closure;
    }
  }
  return std::nullopt;
}

std::optional<DetectedLoopClosure> LoopClosureDetector::verifyObjects(
    const SceneGraphProcessor& processor, const Entry& query, const Entry& candidate) {
  const SceneGraph& graph = processor.graph();
  // Every same-label pair is a putative correspondence (query's robot frame -> candidate's).
  std::vector<Eigen::Vector3d> source, target;
  std::vector<std::pair<const Node*, const Node*>> pairs;  // (query's, candidate's)
  // (Objects the robots have deleted since the keyframes were described are skipped.)
  for (const NodeId q : query.d.objects) {
    const Node* a = graph.findNode(q);
    if (a == nullptr) continue;
    for (const NodeId c : candidate.d.objects) {
      const Node* b = graph.findNode(c);
      if (b == nullptr || a->semantic()->label != b->semantic()->label) continue;
      source.push_back(a->position);
      target.push_back(b->position);
      pairs.emplace_back(a, b);
      if (source.size() >= kMaxObjectPairs) break;
    }
    if (source.size() >= kMaxObjectPairs) break;
  }
  const auto registration = tlsRegistration(source, target, options_.objects);
  if (!registration) return std::nullopt;
  const Eigen::Isometry3d T_candidate_query = registration.value().T_target_source;
  if (ambiguous(source, target, registration.value())) return std::nullopt;
  DetectedLoopClosure closure;
  closure.robot_a = candidate.robot;
  closure.robot_b = query.robot;
  closure.keyframe_a = candidate.d.keyframe;
  closure.keyframe_b = query.d.keyframe;
  if (options_.anchor_objects && closure.interRobot()) {
    // Each side at the keyframe of its robot nearest the median time its inlier objects were
    // mapped: the objects carry the drift of that moment, not of the keyframe that described them.
    // (Not within one robot: there both sides may hold the same objects, mapped once.)
    std::vector<int64_t> query_times, candidate_times;
    for (const size_t i : registration.value().inliers) {
      query_times.push_back(pairs[i].first->last_update_time_ns);
      candidate_times.push_back(pairs[i].second->last_update_time_ns);
    }
    closure.keyframe_a = processor.keyframeNearest(candidate.robot, median(candidate_times))
                             .value_or(candidate.d.keyframe);
    closure.keyframe_b =
        processor.keyframeNearest(query.robot, median(query_times)).value_or(query.d.keyframe);
  }
  closure.T_a_b = nodePose(graph.getNode(closure.keyframe_a)).inverse() * T_candidate_query *
                  nodePose(graph.getNode(closure.keyframe_b));
  closure.information = informationFromVariances(std::pow(options_.object_translation_sigma, 2),
                                                 std::pow(options_.object_rotation_sigma, 2));
  closure.source = DetectedLoopClosure::Source::kObjects;
  closure.inliers = registration.value().inliers.size();
  const std::map<uint32_t, size_t>& label_objects = processor.objectsPerLabel();
  const size_t objects = graph.numNodes(Layer::kObjects);
  for (const size_t i : registration.value().inliers) {
    const auto n = label_objects.find(pairs[i].first->semantic()->label);
    const size_t count = n == label_objects.end() ? 1 : std::max<size_t>(1, n->second);
    closure.distinctiveness += std::log(double(std::max(objects, count)) / double(count));
  }
  return closure;
}

bool LoopClosureDetector::ambiguous(const std::vector<Eigen::Vector3d>& source,
                                    const std::vector<Eigen::Vector3d>& target,
                                    const RegistrationResult& best) const {
  if (options_.object_ambiguity_ratio <= 0.0 || best.inliers.empty()) return false;
  const auto rival = tlsRivalRegistration(source, target, best, options_.objects);
  if (!rival || double(rival.value().inliers.size()) <
                    options_.object_ambiguity_ratio * double(best.inliers.size()))
    return false;
  // A rival at (nearly) the same pose is the same match again (objects seen twice).
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const size_t i : best.inliers) centroid += source[i];
  centroid /= double(best.inliers.size());
  return (best.T_target_source * centroid - rival.value().T_target_source * centroid).norm() >
         options_.object_rival_distance;
}

std::optional<DetectedLoopClosure> LoopClosureDetector::verifyVisual(
    const SceneGraphProcessor& processor, const Entry& query, const Entry& candidate) {
  const RobotFrontendState* qs = processor.robot(query.robot);
  const RobotFrontendState* cs = processor.robot(candidate.robot);
  if (qs == nullptr || cs == nullptr) return std::nullopt;
  const auto qd = qs->descriptors.find(query.d.keyframe);
  const auto cd = cs->descriptors.find(candidate.d.keyframe);
  if (qd == qs->descriptors.end() || cd == cs->descriptors.end()) return std::nullopt;
  // Keypoints matched by word id (a few pairs per word at most).
  std::multimap<uint32_t, const Keypoint*> by_word;
  for (const Keypoint& k : cd->second.keypoints) by_word.emplace(k.word, &k);
  std::vector<Eigen::Vector3d> source, target;
  std::vector<uint32_t> words;
  for (const Keypoint& k : qd->second.keypoints) {
    const auto [first, last] = by_word.equal_range(k.word);
    size_t n = 0;
    for (auto it = first; it != last && n < kMaxPairsPerWord; ++it, ++n) {
      source.push_back(k.position.cast<double>());
      target.push_back(it->second->position.cast<double>());
      words.push_back(k.word);
    }
  }
  RansacOptions ransac = options_.visual;
  ransac.min_inliers = std::max(ransac.min_inliers, options_.visual_min_inliers);
  const auto registration = ransacRegistration(source, target, ransac);
  if (!registration) return std::nullopt;
  DetectedLoopClosure closure;
  closure.robot_a = candidate.robot;
  closure.robot_b = query.robot;
  closure.keyframe_a = candidate.d.keyframe;
  closure.keyframe_b = query.d.keyframe;
  closure.T_a_b = registration.value().T_target_source;  // query body -> candidate body
  closure.information = informationFromVariances(std::pow(options_.visual_translation_sigma, 2),
                                                 std::pow(options_.visual_rotation_sigma, 2));
  closure.source = DetectedLoopClosure::Source::kVisual;
  closure.inliers = registration.value().inliers.size();
  for (const size_t i : registration.value().inliers) {
    const auto it = word_keyframes_.find(words[i]);
    const size_t n = it == word_keyframes_.end() ? 1 : std::max<size_t>(1, it->second);
    closure.distinctiveness += std::log(double(std::max(n, described_.size())) / double(n));
  }
  return closure;
}

}  // namespace hydra_multi
