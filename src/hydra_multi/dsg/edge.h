#pragma once
// Undirected, weighted edges. Inside a layer an edge joins siblings (place-place adjacency,
// odometry between consecutive agent poses); across layers the node of the higher level is the
// parent.

#include <utility>

#include "hydra_multi/core/node_id.h"

namespace hydra_multi {

struct EdgeAttributes {
  double weight = 1.0;  ///< for places: the minimum free-space distance along the edge
  bool weighted = false;
  bool operator==(const EdgeAttributes& o) const {
    return weight == o.weight && weighted == o.weighted;
  }
};

/// The two endpoints of an undirected edge, smaller id first.
class EdgeKey {
 public:
  EdgeKey(NodeId a, NodeId b) : first_(a < b ? a : b), second_(a < b ? b : a) {}
  NodeId first() const { return first_; }
  NodeId second() const { return second_; }
  bool operator==(const EdgeKey& o) const { return first_ == o.first_ && second_ == o.second_; }
  bool operator<(const EdgeKey& o) const {
    return first_ < o.first_ || (first_ == o.first_ && second_ < o.second_);
  }

 private:
  NodeId first_, second_;
};

struct Edge {
  NodeId source;
  NodeId target;
  EdgeAttributes info;
  EdgeKey key() const { return {source, target}; }
  bool operator==(const Edge& o) const { return key() == o.key() && info == o.info; }
};

}  // namespace hydra_multi
