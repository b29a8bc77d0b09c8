#include "hydra_multi/dsg/robot_stream.h"

#include <set>

namespace hydra_multi {

Status applyToRobotGraph(SceneGraph& graph, const RobotUpdate& update) {
  if (!update.is_snapshot) return applyDelta(graph, update.graph);
  auto whole = graphFromSnapshot(update.graph);
  if (!whole) return Error{whole.error()};
  graph = std::move(whole).value();
  return Status::Ok();
}

SequencedUpdate RobotStreamReplay::add(const RobotUpdate& update, const Applied& applied) {
  const auto refuse = [this](std::string why) {
    order_.refuse();
    SequencedUpdate result;
    result.message = std::move(why);
    return result;
  };
  if (Status valid = validateRobotUpdate(update); !valid) return refuse(valid.message());
  if (update.robot != robot_)
    return refuse("update " + std::to_string(update.sequence) + " is from robot " +
                  update.robot.str() + ", not " + robot_.str());
  return order_.offer(update, [&](const RobotUpdate& u) -> Status {
    if (Status s = applyToRobotGraph(graph_, u); !s) return s;
    if (applied) applied(u, graph_);
    return Status::Ok();
  });
}

Status RobotStreamState::add(const RobotUpdate& update) {
  const std::string at = "update " + std::to_string(update.sequence) + " of robot " +
                         (update.robot.isValid() ? update.robot.str() : "?");
  if (Status valid = validateRobotUpdate(update); !valid) return valid;
  if (!update.is_snapshot) {
    if (!started_) return Error{at + ": the first update of a stream must be a snapshot"};
    if (update.robot != last_.robot)
      return Error{at + ": the stream is robot " + last_.robot.str() + "'s"};
    if (update.sequence != last_.sequence + 1)
      return Error{at + ": expected sequence " + std::to_string(last_.sequence + 1)};
  }
  if (Status applied = applyToRobotGraph(graph_, update); !applied)
    return Error{at + ": " + applied.message()};
  if (update.is_snapshot) {
    pose_graph_.clear();
    deformation_ = {};
    descriptors_.clear();
    added_ = 0;
  }
  pose_graph_.insert(pose_graph_.end(), update.pose_graph.begin(), update.pose_graph.end());
  deformation_.points.insert(deformation_.points.end(), update.deformation.points.begin(),
                             update.deformation.points.end());
  deformation_.edges.insert(deformation_.edges.end(), update.deformation.edges.begin(),
                            update.deformation.edges.end());
  for (const KeyframeDescriptor& d : update.descriptors) descriptors_[d.keyframe] = d;
  last_.robot = update.robot;
  last_.sequence = update.sequence;
  last_.time_ns = update.time_ns;
  last_.provided_layers = update.provided_layers;
  started_ = true;
  ++added_;
  return Status::Ok();
}

RobotUpdate RobotStreamState::snapshot() const {
  RobotUpdate s;
  s.robot = last_.robot;
  s.sequence = last_.sequence;
  s.time_ns = last_.time_ns;
  s.provided_layers = last_.provided_layers;
  s.is_snapshot = true;
  s.graph = snapshotOf(graph_);
  const auto kept = [this](NodeId keyframe) { return graph_.hasNode(keyframe); };
  for (const PoseGraphEdge& e : pose_graph_)
    if (kept(e.from) && kept(e.to)) s.pose_graph.push_back(e);
  std::set<uint64_t> points;
  for (const ControlPoint& p : deformation_.points) {
    if (!kept(p.keyframe)) continue;
    s.deformation.points.push_back(p);
    points.insert(p.id);
  }
  for (const ControlPointEdge& e : deformation_.edges)
    if (points.count(e.from) && points.count(e.to)) s.deformation.edges.push_back(e);
  for (const auto& [keyframe, d] : descriptors_)
    if (kept(keyframe)) s.descriptors.push_back(d);
  return s;
}

}  // namespace hydra_multi
