#include "hydra_multi/optim/io/g2o_format.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

#include "hydra_multi/dsg/io/graph_file.h"

namespace hydra_multi::io {
namespace {

// Reads numbers from one line, failing with the token's position.
class LineReader {
 public:
  explicit LineReader(const std::string& line) : in_(line) {}
  bool word(std::string& out) { return static_cast<bool>(in_ >> out); }
  double number(const char* what) {
    std::string token;
    if (!(in_ >> token)) throw std::runtime_error(std::string("missing ") + what);
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') {
      throw std::runtime_error(std::string("'") + token + "' is not a number (" + what + ")");
    }
    if (!std::isfinite(value)) throw std::runtime_error(std::string(what) + " is not finite");
    return value;
  }
  /// Three numbers in order (function arguments have no evaluation order in C++, so never read
  /// them as Vector3d(number(), number(), number())).
  Eigen::Vector3d vector3(const char* x, const char* y, const char* z) {
    Eigen::Vector3d v;
    v.x() = number(x);
    v.y() = number(y);
    v.z() = number(z);
    return v;
  }
  uint64_t id(const char* what) {
    std::string token;
    if (!(in_ >> token)) throw std::runtime_error(std::string("missing ") + what);
    char* end = nullptr;
    errno = 0;
    const unsigned long long value = std::strtoull(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0' || errno != 0 || token[0] == '-') {
      throw std::runtime_error(std::string("'") + token + "' is not a vertex id (" + what + ")");
    }
    return value;
  }
  void end() {
    std::string extra;
    if (in_ >> extra) throw std::runtime_error("unexpected extra value '" + extra + "'");
  }

 private:
  std::istringstream in_;
};

Eigen::Quaterniond readQuaternion(LineReader& r) {
  const double x = r.number("qx"), y = r.number("qy"), z = r.number("qz"), w = r.number("qw");
  Eigen::Quaterniond q(w, x, y, z);
  const double norm = q.norm();
  if (std::abs(norm - 1.0) > 1e-2) {
    throw std::runtime_error("quaternion norm " + std::to_string(norm) + " is not 1");
  }
  return q.normalized();
}

Eigen::Isometry3d makePose(const Eigen::Vector3d& t, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

Eigen::Matrix3d rollPitchYaw(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

template <typename M>
bool positiveDefinite(const M& m) {
  return m.llt().info() == Eigen::Success;
}

// An information matrix the solver can use: positive definite (a Cholesky factor exists), so
// every residual has a weight and the cost is a sum of squares. One that is not, but whose
// translation and rotation blocks (`t` x `t` first, then the rest) are, is weighed as SE-Sync
// weighs it (residuals.h): `note` says so. One whose blocks are not either gives no weight.
template <int N>
void checkInformation(const Eigen::Matrix<double, N, N>& info, int t, std::string& note) {
  if (positiveDefinite(info)) return;
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>>(info).eigenvalues().minCoeff();
  std::ostringstream s;
  s << "the information matrix is not positive definite (smallest eigenvalue " << smallest << ")";
  const Eigen::MatrixXd translation = info.topLeftCorner(t, t);
  const Eigen::MatrixXd rotation = info.bottomRightCorner(N - t, N - t);
  if (!positiveDefinite(translation) || !positiveDefinite(rotation)) {
    s << ", nor is its " << (positiveDefinite(translation) ? "rotation" : "translation")
      << " block: no weight can be derived from it";
    throw std::runtime_error(s.str());
  }
  s << "; weighed by its translation and rotation blocks (SE-Sync's tau and kappa) in the chordal "
       "solve, by its nearest positive-definite matrix in the geodesic one";
  note = s.str();
}

Matrix6d readUpperTriangle6(LineReader& r, std::string& note) {
  Matrix6d info;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) info(i, j) = info(j, i) = r.number("information");
  }
  checkInformation(info, 3, note);
  return info;
}

// Parses the values of one record (after its tag) into `graph`; false for an unknown tag. `note`
// receives what the reader did with an odd value it kept.
bool parseRecord(const std::string& tag, LineReader& r, PoseGraph& graph, std::string& note) {
  if (tag == "VERTEX_SE3:QUAT") {
    const NodeId id(r.id("vertex id"));
    const Eigen::Vector3d t = r.vector3("x", "y", "z");
    graph.poses[id] = makePose(t, readQuaternion(r).toRotationMatrix());
  } else if (tag == "EDGE_SE3:QUAT" || tag == "EDGE3") {
    PoseGraphEdge edge;
    edge.from = NodeId(r.id("edge from"));
    edge.to = NodeId(r.id("edge to"));
    const Eigen::Vector3d t = r.vector3("x", "y", "z");
    Eigen::Matrix3d R;
    if (tag == "EDGE3") {
      const double roll = r.number("roll"), pitch = r.number("pitch"), yaw = r.number("yaw");
      R = rollPitchYaw(roll, pitch, yaw);
    } else {
      R = readQuaternion(r).toRotationMatrix();
    }
    edge.T_from_to = makePose(t, R);
    edge.information = readUpperTriangle6(r, note);
    graph.edges.push_back(edge);
  } else if (tag == "VERTEX3") {
    const NodeId id(r.id("vertex id"));
    const Eigen::Vector3d t = r.vector3("x", "y", "z");
    const double roll = r.number("roll"), pitch = r.number("pitch"), yaw = r.number("yaw");
    graph.poses[id] = makePose(t, rollPitchYaw(roll, pitch, yaw));
  } else if (tag == "VERTEX_SE2") {
    const NodeId id(r.id("vertex id"));
    const double x = r.number("x"), y = r.number("y"), theta = r.number("theta");
    graph.poses[id] = makePose({x, y, 0.0}, rollPitchYaw(0, 0, theta));
  } else if (tag == "EDGE_SE2") {
    PoseGraphEdge edge;
    edge.from = NodeId(r.id("edge from"));
    edge.to = NodeId(r.id("edge to"));
    const double dx = r.number("dx"), dy = r.number("dy"), dtheta = r.number("dtheta");
    edge.T_from_to = makePose({dx, dy, 0.0}, rollPitchYaw(0, 0, dtheta));
    // 2D information over (x, y, theta) -> 3D order (x, y, z, roll, pitch, yaw).
    const int map[3] = {0, 1, 5};
    Eigen::Matrix3d info2;
    for (int i = 0; i < 3; ++i) {
      for (int j = i; j < 3; ++j) info2(i, j) = info2(j, i) = r.number("information");
    }
    checkInformation(info2, 2, note);
    edge.information.setZero();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) edge.information(map[i], map[j]) = info2(i, j);
    }
    const double planar = info2.diagonal().maxCoeff();
    for (const int k : {2, 3, 4}) edge.information(k, k) = planar;
    graph.edges.push_back(edge);
  } else {
    return false;
  }
  return true;
}

// Parses one line into the graph; returns the tag of a line this reader skips (empty for a line
// it read or a blank one). The graph changes only when the whole line is valid.
std::string parseLine(const std::string& line, PoseGraph& graph, std::string& note) {
  LineReader r(line);
  std::string tag;
  if (!r.word(tag) || tag[0] == '#') return "";  // blank line or comment
  PoseGraph parsed;
  const bool known = parseRecord(tag, r, parsed, note);
  if (!known) return tag;
  r.end();
  for (auto& [id, T] : parsed.poses) graph.poses[id] = T;
  graph.edges.insert(graph.edges.end(), parsed.edges.begin(), parsed.edges.end());
  return "";
}

// A tag for a message: printable, at most 24 characters.
std::string printable(const std::string& tag) {
  std::string out;
  for (const char c : tag.substr(0, 24))
    out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return tag.size() > 24 ? out + "..." : out;
}

}  // namespace

Result<G2oFile> parseG2o(const std::string& text, const std::string& name,
                         const G2oReadOptions& options) {
  if (const size_t nul = text.find('\0'); nul != std::string::npos)
    return Error{name + ": not a text file (byte " + std::to_string(nul) +
                 " is 0): not a g2o or TORO file"};
  G2oFile file;
  std::istringstream in(text);
  std::string line;
  size_t line_number = 0, first_skipped = 0;
  std::string first_tag;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    try {
      std::string note;
      const std::string skipped = parseLine(line, file.graph, note);
      if (!note.empty())
        file.notes.push_back(name + ":" + std::to_string(line_number) + ": " + note);
      if (skipped.empty()) continue;
      ++file.skipped_lines;
      ++file.skipped_tags[printable(skipped)];
      if (first_skipped == 0) {
        first_skipped = line_number;
        first_tag = printable(skipped);
      }
    } catch (const std::exception& error) {
      const std::string message = name + ":" + std::to_string(line_number) + ": " + error.what();
      if (!options.skip_bad_lines) return Error{message};
      file.warnings.push_back(message);
      ++file.skipped_lines;
    }
  }
  if (file.graph.poses.empty() && file.graph.edges.empty()) {
    return Error{name + ": no vertex or edge in " + std::to_string(line_number) + " lines" +
                 (first_skipped > 0 ? " (line " + std::to_string(first_skipped) + " starts with '" +
                                          first_tag + "')"
                                    : std::string()) +
                 ": not a g2o or TORO file"};
  }
  if (!file.skipped_tags.empty()) {
    std::string tags;
    size_t shown = 0;
    for (const auto& [tag, count] : file.skipped_tags) {
      if (shown++ == 5) {
        tags += ", ...";
        break;
      }
      tags += (tags.empty() ? "" : ", ") + tag + " " + std::to_string(count);
    }
    const size_t lines = file.skipped_lines - file.warnings.size();
    file.warnings.push_back(name + ": " + std::to_string(lines) + " of " +
                            std::to_string(line_number) +
                            " lines not read, their tags unknown to " + "this reader (" + tags +
                            "), first at line " + std::to_string(first_skipped));
  }
  return file;
}

Result<G2oFile> readG2o(const std::string& path, const G2oReadOptions& options) {
  auto text = readFile(path);
  if (!text) return Error{text.error()};
  return parseG2o(text.value(), path, options);
}

Result<MergedG2o> readAndMergeG2o(const std::vector<std::string>& paths,
                                  const G2oReadOptions& options) {
  MergedG2o merged;
  std::set<std::pair<NodeId, NodeId>> earlier_edges;
  for (size_t f = 0; f < paths.size(); ++f) {
    auto file = readG2o(paths[f], options);
    if (!file) return Error{file.error()};
    const PoseGraph& g = file.value().graph;
    merged.warnings.insert(merged.warnings.end(), file.value().warnings.begin(),
                           file.value().warnings.end());
    merged.notes.insert(merged.notes.end(), file.value().notes.begin(), file.value().notes.end());
    for (const auto& [id, T] : g.poses) {
      merged.graph.poses.emplace(id, T);
      merged.node_owner.emplace(id, f);
    }
    std::set<std::pair<NodeId, NodeId>> this_file;
    for (const PoseGraphEdge& edge : g.edges) {
      const auto key = std::minmax(edge.from, edge.to);
      if (earlier_edges.count(key)) {
        ++merged.duplicate_edges;
        continue;
      }
      this_file.insert(key);
      merged.graph.edges.push_back(edge);
      merged.edge_file.push_back(f);
      const bool step =
          edge.from.category() == edge.to.category() &&
          (edge.from.index() + 1 == edge.to.index() || edge.to.index() + 1 == edge.from.index());
      if (step) {
        merged.node_owner.emplace(edge.from, f);
        merged.node_owner.emplace(edge.to, f);
      }
    }
    earlier_edges.insert(this_file.begin(), this_file.end());
  }
  classifyEdges(merged.graph, std::max<size_t>(1, paths.size()));
  for (PoseGraphEdge& edge : merged.graph.edges) {
    const auto a = merged.node_owner.find(edge.from), b = merged.node_owner.find(edge.to);
    if (a != merged.node_owner.end() && b != merged.node_owner.end() && a->second != b->second) {
      edge.kind = PoseGraphEdge::Kind::kLoopClosure;
    }
  }
  return merged;
}

std::string writeG2o(const PoseGraph& graph) {
  std::ostringstream out;
  out << std::setprecision(17);
  for (const auto& [id, T] : graph.poses) {
    const Eigen::Quaterniond q(T.linear());
    out << "VERTEX_SE3:QUAT " << id.value() << " " << T.translation().x() << " "
        << T.translation().y() << " " << T.translation().z() << " " << q.x() << " " << q.y() << " "
        << q.z() << " " << q.w() << "\n";
  }
  for (const PoseGraphEdge& e : graph.edges) {
    const Eigen::Quaterniond q(e.T_from_to.linear());
    const Eigen::Vector3d& t = e.T_from_to.translation();
    out << "EDGE_SE3:QUAT " << e.from.value() << " " << e.to.value() << " " << t.x() << " " << t.y()
        << " " << t.z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w();
    for (int i = 0; i < 6; ++i) {
      for (int j = i; j < 6; ++j) out << " " << e.information(i, j);
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace hydra_multi::io
