#pragma once
// Spark-DSG's binary scene-graph layout (../shared/reference/spark-dsg-wire.md §1), formats 1.0.2
// to 1.1.4: the file form (`.sparkdsg`: a header naming the project and version, then the graph)
// and the wire form of its ZeroMQ messages (the graph alone; its version is the sender's, which
// the caller gives). Every scalar is a tag byte and its little-endian payload; arrays and strings
// are ARR32 with a count; nodes and edges are dynamic arrays (00 ... 01) of records whose
// attributes follow their type's field order with no framing. What changed between versions is
// read and written as Spark-DSG's writers of each version wrote it (§1.10, checked against
// Spark-DSG built at those versions): before 1.1.2 layer ids, not keys, unsigned before 1.1.0 (as
// a node's layer then);
// before 1.1.1 (1.1.0) layer names map to ids, before 1.1.0 there are none; before 1.1.0 a node
// record carries an optional stamp instead of its partition (a stamped node is a dynamic node of
// the partition of its prefix: agents) and the dynamic nodes follow in an array of their own;
// before 1.0.6 no metadata; before 1.0.4 no is_predicted, but places a predicted_place, and
// colours without alpha; up to 1.0.4 semantic features in double precision; before 1.0.3 boxes by
// min and max; before 1.1.0 agents carry no timestamp (the record's stamp is theirs), before
// 1.1.3 places no anti_frontier; from 1.1.4 2D places have their new layout.
//
// spark::Graph holds everything a message carries, field by field, so that encoding a decoded
// graph in its version writes the same bytes. The decoder checks what Spark-DSG does not: every
// tag, every fixed array's length, every count against the bytes left, type ids against the
// message's own names table, names against the types it knows, finite numbers; an error names the
// byte offset and the field, and nothing is read past the buffer.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hydra_multi/core/result.h"

namespace hydra_multi::io::spark {

struct Version {
  uint8_t major = 1, minor = 1, patch = 3;
  std::string str() const;
  /// "1.1.3" and the like; nullopt for anything else.
  static std::optional<Version> parse(const std::string& text);
  constexpr uint32_t key() const {
    return (uint32_t(major) << 16) | (uint32_t(minor) << 8) | patch;
  }
  constexpr bool operator==(const Version& o) const { return key() == o.key(); }
  constexpr bool operator<(const Version& o) const { return key() < o.key(); }
  constexpr bool operator<=(const Version& o) const { return key() <= o.key(); }
};
/// The version written unless another is asked for (the fixtures' and Hydra main's).
inline constexpr Version kVersion{1, 1, 3};
/// The versions this codec reads and writes: Spark-DSG refuses files older than 1.0.2; 1.1.4 is
/// its develop branch's.
inline constexpr Version kOldestVersion{1, 0, 2}, kNewestVersion{1, 1, 4};
/// Empty when `version` is one this codec reads and writes, else why not.
std::string unsupported(const Version& version);

struct LayerKey {
  int64_t layer = 0;
  uint32_t partition = 0;
  bool operator==(const LayerKey& o) const { return layer == o.layer && partition == o.partition; }
};

/// A generic Eigen matrix as written (rows, cols, elements row-major, each with `tag`).
struct Matrix {
  int64_t rows = 0, cols = 0;
  uint8_t tag = 0xca;  ///< the elements' scalar tag (FLOAT32 0xca, FLOAT64 0xcb, UINT32 0xce)
  std::vector<double> values;
  bool operator==(const Matrix& o) const {
    return rows == o.rows && cols == o.cols && tag == o.tag && values == o.values;
  }
};

struct BoundingBox {
  int32_t type = 0;  ///< 0 invalid, 1 AABB, 2 OBB, 3 RAABB
  std::array<float, 3> dimensions{};
  std::array<float, 3> center{};
  Matrix rotation;  ///< world_R_center, 3x3 FLOAT32
  /// Before 1.0.3: the min and max the box was written with (its dimensions are their difference).
  std::optional<std::array<std::array<float, 3>, 2>> min_max;
  bool operator==(const BoundingBox& o) const {
    return type == o.type && dimensions == o.dimensions && center == o.center &&
           rotation == o.rotation;
  }
};

struct NearestVertex {
  std::array<int32_t, 3> block{};
  std::array<double, 3> voxel{};
  uint64_t vertex = 0;
  std::optional<uint32_t> label;
  bool operator==(const NearestVertex& o) const {
    return block == o.block && voxel == o.voxel && vertex == o.vertex && label == o.label;
  }
};

using Quaternion = std::array<double, 4>;  ///< w, x, y, z

/// One node's or edge's attributes: the fields of its type and of the types it derives from
/// (the others stay at their defaults and are not written).
struct Attributes {
  std::string type;  ///< a registered name, e.g. "PlaceNodeAttributes"
  std::string metadata = "{}";
  // NodeAttributes
  std::array<double, 3> position{};
  uint64_t last_update_time_ns = 0;
  bool is_active = false, is_predicted = false;
  // SemanticNodeAttributes
  std::string name;
  std::array<uint8_t, 4> color{0, 0, 0, 255};
  BoundingBox bounding_box;
  uint32_t semantic_label = 0xFFFFFFFF;
  Matrix semantic_feature;
  // ObjectNodeAttributes
  std::vector<uint64_t> mesh_connections;
  bool registered = false;
  Quaternion world_R_object{1, 0, 0, 0};
  // RoomNodeAttributes
  std::vector<std::pair<std::string, double>> semantic_class_probabilities;
  // PlaceNodeAttributes
  double distance = 0.0;
  uint32_t num_basis_points = 0;
  std::vector<NearestVertex> voxblox_mesh_connections;
  std::vector<uint64_t> pcl_mesh_connections;
  std::vector<uint8_t> mesh_vertex_labels;
  std::vector<uint64_t> deformation_connections;
  bool real_place = true, predicted_place = false;  ///< predicted_place: up to 1.0.3
  bool active_frontier = false;
  std::array<double, 3> frontier_scale{};
  Quaternion orientation{1, 0, 0, 0};
  bool need_cleanup = false;
  uint64_t num_frontier_voxels = 0;
  bool anti_frontier = false;
  // Place2dNodeAttributes: up to 1.1.3 (from 1.1.4 mesh_connections and boundary_connections
  // are pcl_mesh_connections and pcl_boundary_connections, and the last three fields are new)
  std::vector<std::array<double, 3>> boundary;
  std::array<double, 3> ellipse_centroid{};
  Matrix ellipse_matrix_compress, ellipse_matrix_expand;
  std::vector<uint64_t> pcl_boundary_connections;
  bool need_cleanup_splitting = false, has_active_mesh_indices = false;
  uint64_t min_mesh_index = 0, max_mesh_index = 0;
  bool need_finish_merge = false;
  // AgentNodeAttributes
  int64_t timestamp_ns = 0;
  Quaternion world_R_body{1, 0, 0, 0};
  uint64_t external_key = 0;
  Matrix dbow_ids, dbow_values;
  // EdgeAttributes
  bool weighted = false;
  double weight = 1.0;
};

struct Node {
  int64_t layer = 0;
  uint64_t id = 0;  ///< bits 56-63 the prefix character, 0-55 the index
  uint32_t partition = 0;
  /// Before 1.1.0: the record's stamp (ns), set on dynamic nodes (their partition is their
  /// prefix character); an agent's timestamp then.
  std::optional<int64_t> stamp_ns;
  uint8_t type_id = 0;  ///< into SparkGraph::node_types
  Attributes attributes;
};

struct Edge {
  uint64_t source = 0, target = 0;
  uint8_t type_id = 0;  ///< into SparkGraph::edge_types
  Attributes attributes;
};

struct Mesh {
  bool has_colors = false, has_stamps = false, has_labels = false, has_first_seen = false;
  std::vector<std::array<float, 3>> points;
  std::vector<std::array<uint8_t, 4>> colors;
  std::vector<uint64_t> stamps;
  std::vector<uint32_t> labels;
  std::vector<uint64_t> first_seen_stamps;
  std::vector<std::array<uint64_t, 3>> faces;
};

struct Graph {
  std::vector<LayerKey> layer_keys;
  std::vector<std::string> node_types, edge_types;
  std::vector<std::pair<std::string, LayerKey>> layer_names;  ///< sorted by name
  std::string metadata = "{}";
  std::vector<Node> nodes;
  std::vector<Edge> edges;
  std::optional<Mesh> mesh;  ///< absent: the flag said no mesh (c2)
};

struct FileHeader {
  std::string project = "main";
  Version version = kVersion;
};

/// The wire form (a ZeroMQ message's bytes). `version`: the sender's Spark-DSG (the wire has
/// none).
Result<Graph> decodeWire(std::string_view bytes, Version version = kVersion);
/// The file form, in the version its header names; `header`, when given, receives the header.
Result<Graph> decodeFile(std::string_view bytes, FileHeader* header = nullptr);

/// In `version`'s layout (throws std::invalid_argument for a version unsupported() refuses).
/// What a version has no field for is not written.
std::string encodeWire(const Graph& graph, Version version = kVersion);
std::string encodeFile(const Graph& graph, const FileHeader& header = {});
/// The file form's header alone: a message in the wire form after it is a .sparkdsg file.
std::string encodeFileHeader(const FileHeader& header = {});

/// The node types this codec knows (it refuses a names table with others).
const std::vector<std::string>& knownNodeTypes();

}  // namespace hydra_multi::io::spark
