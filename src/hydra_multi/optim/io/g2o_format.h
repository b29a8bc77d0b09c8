#pragma once
// g2o and TORO pose-graph files.
//
//   VERTEX_SE3:QUAT id x y z qx qy qz qw
//   EDGE_SE3:QUAT   i j x y z qx qy qz qw  I (21 values: upper triangle of the 6x6 information,
//                                           row by row, translation first)
//   VERTEX_SE2      id x y theta                          (lifted to 3D with z = 0)
//   EDGE_SE2        i j dx dy dtheta I11 I12 I13 I22 I23 I33
//   VERTEX3         id x y z roll pitch yaw               (TORO; R = Rz(yaw) Ry(pitch) Rx(roll))
//   EDGE3           i j x y z roll pitch yaw I (21 values, same layout)
//
// Ids are kept as 64-bit keys (GTSAM symbols carry the robot's letter in the top byte). An SE(2)
// edge's information on x, y, yaw goes to the matching entries of the 6x6 matrix; z, roll and
// pitch, which 2D data does not measure, get the largest diagonal entry of the 2D information, so
// lifted graphs stay planar. Other tags (FIX, PARAMS_SE3OFFSET, ...) are skipped and counted, and
// said in a warning; '#' starts a comment line. A file that is not text, or holds no vertex and no
// edge, is refused. An edge whose information matrix is not positive definite is read, weighed as
// SE-Sync weighs it (optim/residuals.h), and named in a note with file and line; one whose
// translation or rotation block is not positive definite either is refused (no weight can be
// derived from it; its cost would be no sum of squares), naming file and line.

#include <map>
#include <string>
#include <unordered_map>

#include "hydra_multi/core/result.h"
#include "hydra_multi/optim/pose_graph.h"

namespace hydra_multi::io {

struct G2oReadOptions {
  /// Report a malformed line and go on, instead of failing on it.
  bool skip_bad_lines = false;
};

struct G2oFile {
  PoseGraph graph;
  size_t skipped_lines = 0;                    ///< unknown tags, and bad lines with skip_bad_lines
  std::map<std::string, size_t> skipped_tags;  ///< unknown tags and their lines
  /// One per bad line skipped, naming file and line; then one for the lines of unknown tags.
  std::vector<std::string> warnings;
  /// One per line read but weighed otherwise than as written (an edge whose information matrix
  /// is not positive definite), naming file and line.
  std::vector<std::string> notes;
};

/// Parses g2o/TORO text; `name` is used in messages ("<name>:<line>: ...").
Result<G2oFile> parseG2o(const std::string& text, const std::string& name,
                         const G2oReadOptions& options = {});
Result<G2oFile> readG2o(const std::string& path, const G2oReadOptions& options = {});

/// Several files merged into one graph, e.g. one file per robot plus a file of loop closures.
struct MergedG2o {
  PoseGraph graph;
  std::vector<size_t> edge_file;                  ///< the file each edge came from
  std::unordered_map<NodeId, size_t> node_owner;  ///< the file that owns each node (see below)
  size_t duplicate_edges = 0;                     ///< edges an earlier file already gave
  std::vector<std::string> warnings;
  std::vector<std::string> notes;  ///< of every file (G2oFile::notes)
};

/// Reads and merges files. Poses: the first file that gives one wins. An edge between the same
/// two nodes as an edge of an earlier file counts once. A node is owned by the first file that
/// gives its vertex or an edge from it to a consecutive id. Edges are classified (classifyEdges,
/// at most one odometry piece per file), and an edge between nodes of different owners is always
/// a loop closure.
Result<MergedG2o> readAndMergeG2o(const std::vector<std::string>& paths,
                                  const G2oReadOptions& options = {});

/// g2o text: VERTEX_SE3:QUAT for every pose, EDGE_SE3:QUAT for every edge.
std::string writeG2o(const PoseGraph& graph);

}  // namespace hydra_multi::io
