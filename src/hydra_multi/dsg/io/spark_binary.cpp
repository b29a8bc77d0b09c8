#include "hydra_multi/dsg/io/spark_binary.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include "hydra_multi/dsg/io/spark_attributes.h"
#include "hydra_multi/dsg/io/spark_wire.h"

namespace hydra_multi::io::spark {
namespace {

void readMesh(Reader& r, Mesh& m) {
  m.has_colors = r.boolean("mesh has_colors");
  m.has_stamps = r.boolean("mesh has_timestamps");
  m.has_labels = r.boolean("mesh has_labels");
  m.has_first_seen = r.boolean("mesh has_first_seen_stamps");
  readVector(r, m.points, "mesh points", 15,
             [&](std::array<float, 3>& p) { readVector3f(r, p, "mesh points"); });
  readVector(r, m.colors, "mesh colors", 8, [&](std::array<uint8_t, 4>& c) {
    for (uint8_t& x : c) x = r.u8("mesh colors");
  });
  readU64s(r, m.stamps, "mesh stamps");
  readVector(r, m.labels, "mesh labels", 5, [&](uint32_t& x) { x = r.u32("mesh labels"); });
  readU64s(r, m.first_seen_stamps, "mesh first_seen_stamps");
  readVector(r, m.faces, "mesh faces", 32, [&](std::array<uint64_t, 3>& f) {
    r.fixed(3, "mesh faces");
    for (uint64_t& i : f) {
      const size_t at = r.offset();
      i = r.u64("mesh faces");
      if (i >= m.points.size())
        Reader::fail(at, "mesh faces",
                     "vertex " + std::to_string(i) + " of " + std::to_string(m.points.size()));
    }
  });
}

void writeMesh(Writer& w, const Mesh& m) {
  w.boolean(m.has_colors);
  w.boolean(m.has_stamps);
  w.boolean(m.has_labels);
  w.boolean(m.has_first_seen);
  writeVector(w, m.points, [&](const std::array<float, 3>& p) { writeVector3f(w, p); });
  writeVector(w, m.colors, [&](const std::array<uint8_t, 4>& c) {
    for (const uint8_t x : c) w.u8(x);
  });
  writeU64s(w, m.stamps);
  writeVector(w, m.labels, [&](uint32_t x) { w.u32(x); });
  writeU64s(w, m.first_seen_stamps);
  writeVector(w, m.faces, [&](const std::array<uint64_t, 3>& f) {
    w.length(3);
    for (const uint64_t i : f) w.u64(i);
  });
}

// The layer names Spark-DSG assumes before 1.1.0, which wrote none.
const std::vector<std::pair<std::string, LayerKey>>& legacyLayerNames() {
  static const std::vector<std::pair<std::string, LayerKey>> names = {{"AGENTS", {2, 0}},
                                                                      {"BUILDINGS", {5, 0}},
                                                                      {"OBJECTS", {2, 0}},
                                                                      {"PLACES", {3, 0}},
                                                                      {"ROOMS", {4, 0}}};
  return names;
}

// Nodes until the end of a dynamic array; before 1.1.0 a record's third item is an optional
// stamp, and a stamped node is in the partition of its prefix character.
void readNodes(Reader& r, Graph& g, const std::vector<std::optional<Kind>>& kinds, Version v) {
  r.expect(kDynamicBegin, "nodes");
  while (!r.peek(kDynamicEnd)) {
    const size_t at = r.offset();
    try {
      Node n;
      r.fixed(4, "node");
      n.layer =
          v < Version{1, 1, 0} ? static_cast<int64_t>(r.u64("node layer")) : r.i64("node layer");
      n.id = r.u64("node id");
      if (v < Version{1, 1, 0}) {
        if (r.peek(kNil)) {
          r.skip("node stamp");
        } else {
          n.stamp_ns = r.i64("node stamp");
          n.partition = static_cast<uint8_t>(n.id >> 56);
        }
      } else {
        n.partition = r.u32("node partition");
      }
      readAttributes(r, g.node_types, kinds, v, n.type_id, n.attributes);
      if (n.stamp_ns && n.attributes.type == "AgentNodeAttributes")
        n.attributes.timestamp_ns = *n.stamp_ns;
      g.nodes.push_back(std::move(n));
    } catch (const DecodeError& e) {
      throw e.within("node " + std::to_string(g.nodes.size()) + " (at byte " + std::to_string(at) +
                     ")");
    }
  }
  r.skip("nodes");
}

Graph readGraph(Reader& r, Version v) {
  Graph g;
  if (v < Version{1, 1, 2}) {
    // Layer ids were unsigned before 1.1.0.
    readVector(r, g.layer_keys, "layer ids", 9, [&](LayerKey& k) {
      k = {v < Version{1, 1, 0} ? static_cast<int64_t>(r.u64("layer ids")) : r.i64("layer ids"), 0};
    });
  } else {
    readVector(r, g.layer_keys, "layer keys", 20,
               [&](LayerKey& k) { readLayerKey(r, k, "layer keys"); });
  }
  readVector(r, g.node_types, "node attribute names", 5,
             [&](std::string& s) { s = r.string("node attribute names"); });
  readVector(r, g.edge_types, "edge attribute names", 5,
             [&](std::string& s) { s = r.string("edge attribute names"); });
  if (v < Version{1, 1, 0}) {
    g.layer_names = legacyLayerNames();
  } else {
    readVector(r, g.layer_names, "layer names", 14, [&](std::pair<std::string, LayerKey>& p) {
      p.first = r.string("layer names");
      if (v < Version{1, 1, 1})
        p.second = {r.i64("layer names"), 0};
      else
        readLayerKey(r, p.second, "layer names");
    });
  }
  if (Version{1, 0, 6} <= v) g.metadata = r.string("graph metadata");
  const std::vector<std::optional<Kind>> node_kinds = kindsOf(g.node_types);
  const std::vector<std::optional<Kind>> edge_kinds = kindsOf(g.edge_types);
  readNodes(r, g, node_kinds, v);
  if (v < Version{1, 1, 0}) readNodes(r, g, node_kinds, v);  // the dynamic nodes
  r.expect(kDynamicBegin, "edges");
  while (!r.peek(kDynamicEnd)) {
    const size_t at = r.offset();
    try {
      Edge e;
      r.fixed(3, "edge");
      e.source = r.u64("edge source");
      e.target = r.u64("edge target");
      readAttributes(r, g.edge_types, edge_kinds, v, e.type_id, e.attributes);
      g.edges.push_back(std::move(e));
    } catch (const DecodeError& error) {
      throw error.within("edge " + std::to_string(g.edges.size()) + " (at byte " +
                         std::to_string(at) + ")");
    }
  }
  r.skip("edges");
  // A missing mesh flag at the end means no mesh, as Spark-DSG reads it.
  if (!r.atEnd() && r.boolean("mesh flag")) {
    g.mesh.emplace();
    readMesh(r, *g.mesh);
  }
  if (!r.atEnd())
    Reader::fail(r.offset(), "end", std::to_string(r.remaining()) + " bytes after the graph");
  return g;
}

void writeNode(Writer& w, const Graph& g, const Node& n, Version v) {
  w.length(4);
  if (v < Version{1, 1, 0})
    w.u64(static_cast<uint64_t>(n.layer));
  else
    w.i64(n.layer);
  w.u64(n.id);
  if (v < Version{1, 1, 0}) {
    if (n.stamp_ns)
      w.i64(*n.stamp_ns);
    else
      w.tag(kNil);
  } else {
    w.u32(n.partition);
  }
  writeAttributes(w, g.node_types, n.type_id, n.attributes, v);
}

// Before 1.1.0 the nodes of a partition are dynamic nodes, stamped (agents: with their
// timestamp), in an array of their own after the others.
Node legacyDynamic(const Node& n) {
  Node d = n;
  if (!d.stamp_ns)
    d.stamp_ns = n.attributes.type == "AgentNodeAttributes"
                     ? n.attributes.timestamp_ns
                     : int64_t(n.attributes.last_update_time_ns);
  return d;
}

void writeGraph(Writer& w, const Graph& g, Version v) {
  if (v < Version{1, 1, 2}) {
    std::vector<int64_t> ids;
    for (const LayerKey& k : g.layer_keys) {
      if (std::find(ids.begin(), ids.end(), k.layer) == ids.end()) ids.push_back(k.layer);
    }
    writeVector(w, ids, [&](int64_t id) {
      if (v < Version{1, 1, 0})
        w.u64(static_cast<uint64_t>(id));
      else
        w.i64(id);
    });
  } else {
    writeVector(w, g.layer_keys, [&](const LayerKey& k) { writeLayerKey(w, k); });
  }
  writeVector(w, g.node_types, [&](const std::string& s) { w.string(s); });
  writeVector(w, g.edge_types, [&](const std::string& s) { w.string(s); });
  if (Version{1, 1, 0} <= v) {
    writeVector(w, g.layer_names, [&](const std::pair<std::string, LayerKey>& p) {
      w.string(p.first);
      if (v < Version{1, 1, 1})
        w.i64(p.second.layer);
      else
        writeLayerKey(w, p.second);
    });
  }
  if (Version{1, 0, 6} <= v) w.string(g.metadata);
  const bool legacy = v < Version{1, 1, 0};
  w.tag(kDynamicBegin);
  for (const Node& n : g.nodes) {
    if (!legacy || (n.partition == 0 && !n.stamp_ns)) writeNode(w, g, n, v);
  }
  w.tag(kDynamicEnd);
  if (legacy) {
    w.tag(kDynamicBegin);
    for (const Node& n : g.nodes) {
      if (n.partition != 0 || n.stamp_ns) writeNode(w, g, legacyDynamic(n), v);
    }
    w.tag(kDynamicEnd);
  }
  w.tag(kDynamicBegin);
  for (const Edge& e : g.edges) {
    w.length(3);
    w.u64(e.source);
    w.u64(e.target);
    writeAttributes(w, g.edge_types, e.type_id, e.attributes, v);
  }
  w.tag(kDynamicEnd);
  w.boolean(g.mesh.has_value());
  if (g.mesh) writeMesh(w, *g.mesh);
}

Result<Graph> decodeGraph(std::string_view bytes, size_t base, Version version, const char* form) {
  if (const std::string why = unsupported(version); !why.empty())
    return Error{std::string("spark binary (") + form + "): " + why};
  try {
    Reader r(bytes, base);
    return readGraph(r, version);
  } catch (const DecodeError& e) {
    return Error{std::string("spark binary (") + form + ", format " + version.str() +
                 "): " + e.what()};
  }
}

}  // namespace

std::string Version::str() const {
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

std::optional<Version> Version::parse(const std::string& text) {
  unsigned a = 0, b = 0, c = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%u.%u.%u%c", &a, &b, &c, &rest) != 3 || a > 255 || b > 255 ||
      c > 255)
    return std::nullopt;
  const Version v{uint8_t(a), uint8_t(b), uint8_t(c)};
  return v.str() == text ? std::optional<Version>(v) : std::nullopt;
}

std::string unsupported(const Version& version) {
  if (version < kOldestVersion)
    return "format " + version.str() + " is older than " + kOldestVersion.str() +
           ", the oldest Spark-DSG reads";
  if (kNewestVersion < version)
    return "format " + version.str() + " is newer than " + kNewestVersion.str() +
           ", the newest this codec knows";
  return "";
}

const std::vector<std::string>& knownNodeTypes() {
  static const std::vector<std::string> types = {
      "NodeAttributes",      "SemanticNodeAttributes", "ObjectNodeAttributes", "RoomNodeAttributes",
      "PlaceNodeAttributes", "Place2dNodeAttributes",  "AgentNodeAttributes"};
  return types;
}

Result<Graph> decodeWire(std::string_view bytes, Version version) {
  return decodeGraph(bytes, 0, version, "wire");
}

Result<Graph> decodeFile(std::string_view bytes, FileHeader* header) {
  FileHeader h;
  size_t at = 0;
  try {
    Reader r(bytes);
    const std::string magic = r.string("file header");
    if (magic != "SPARK_DSG")
      Reader::fail(0, "file header", "'" + magic + "' is not SPARK_DSG: not a Spark-DSG file");
    h.project = r.string("file header project");
    h.version.major = r.u8("file header version");
    h.version.minor = r.u8("file header version");
    h.version.patch = r.u8("file header version");
    at = r.offset();
  } catch (const DecodeError& e) {
    return Error{std::string("spark binary (file): ") + e.what()};
  }
  if (h.project != "main")
    return Error{"spark binary (file): project '" + h.project +
                 "': Spark-DSG reads only 'main' files"};
  if (header != nullptr) *header = h;
  return decodeGraph(bytes.substr(at), at, h.version, "file");
}

std::string encodeWire(const Graph& graph, Version version) {
  if (const std::string why = unsupported(version); !why.empty())
    throw std::invalid_argument("spark binary: " + why);
  Writer w;
  writeGraph(w, graph, version);
  return w.release();
}

std::string encodeFileHeader(const FileHeader& header) {
  Writer w;
  w.string("SPARK_DSG");
  w.string(header.project);
  w.u8(header.version.major);
  w.u8(header.version.minor);
  w.u8(header.version.patch);
  return w.release();
}

std::string encodeFile(const Graph& graph, const FileHeader& header) {
  return encodeFileHeader(header) + encodeWire(graph, header.version);
}

}  // namespace hydra_multi::io::spark
