#include "hydra_multi/web/viewer_mesh.h"

#include <cstring>

#include <nlohmann/json.hpp>

#include "hydra_multi/web/view_state.h"

namespace hydra_multi::web {
namespace {

template <typename T>
void put(std::string& out, const T& value) {
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

void padTo4(std::string& out, char with) {
  while (out.size() % 4 != 0) out.push_back(with);
}

}  // namespace

std::string encodeViewerMesh(const Mesh& mesh, uint64_t seq) {
  const nlohmann::json header = {{"seq", seq},
                                 {"vertices", mesh.vertices.size()},
                                 {"faces", mesh.faces.size()},
                                 {"robots", meshExtents(mesh)}};
  std::string text = header.dump();
  while ((4 + text.size()) % 4 != 0) text.push_back(' ');
  std::string out;
  out.reserve(4 + text.size() + mesh.vertices.size() * 20 + mesh.faces.size() * 12 + 4);
  put(out, static_cast<uint32_t>(text.size()));
  out += text;
  for (const MeshVertex& v : mesh.vertices) {
    put(out, v.position.x());
    put(out, v.position.y());
    put(out, v.position.z());
  }
  for (const MeshVertex& v : mesh.vertices) {
    out.push_back(static_cast<char>(v.color.r));
    out.push_back(static_cast<char>(v.color.g));
    out.push_back(static_cast<char>(v.color.b));
  }
  padTo4(out, '\0');
  for (const MeshVertex& v : mesh.vertices) put(out, v.label);
  for (const MeshFace& f : mesh.faces) {
    for (const uint32_t i : f) put(out, i);
  }
  return out;
}

Result<Mesh> decodeViewerMesh(const std::string& bytes, uint64_t* seq) {
  const auto fail = [](const std::string& what) { return Error{"viewer mesh: " + what}; };
  if (bytes.size() < 4) return fail("shorter than its 4-byte header length");
  uint32_t header_length = 0;
  std::memcpy(&header_length, bytes.data(), 4);
  if (header_length > bytes.size() - 4)
    return fail("header length " + std::to_string(header_length) + " runs past the " +
                std::to_string(bytes.size()) + " bytes");
  const nlohmann::json header =
      nlohmann::json::parse(bytes.substr(4, header_length), nullptr, false);
  if (header.is_discarded() || !header.is_object() || !header["vertices"].is_number_unsigned() ||
      !header["faces"].is_number_unsigned() || !header["robots"].is_object())
    return fail("the header is not {seq, vertices, faces, robots}");
  const uint64_t n = header["vertices"].get<uint64_t>();
  const uint64_t m = header["faces"].get<uint64_t>();
  size_t at = 4 + header_length;
  const uint64_t colours = (3 * n + 3) / 4 * 4;
  const uint64_t need = at + 12 * n + colours + 4 * n + 12 * m;
  if (n > bytes.size() || m > bytes.size() || need != bytes.size())
    return fail(std::to_string(n) + " vertices and " + std::to_string(m) + " faces need " +
                std::to_string(need) + " bytes, not " + std::to_string(bytes.size()));
  Mesh mesh;
  mesh.vertices.resize(n);
  for (MeshVertex& v : mesh.vertices) {
    std::memcpy(v.position.data(), bytes.data() + at, 12);
    at += 12;
  }
  for (MeshVertex& v : mesh.vertices) {
    v.color = {static_cast<uint8_t>(bytes[at]), static_cast<uint8_t>(bytes[at + 1]),
               static_cast<uint8_t>(bytes[at + 2])};
    at += 3;
  }
  at = 4 + header_length + 12 * n + colours;
  for (MeshVertex& v : mesh.vertices) {
    std::memcpy(&v.label, bytes.data() + at, 4);
    at += 4;
  }
  mesh.faces.resize(m);
  for (MeshFace& f : mesh.faces) {
    std::memcpy(f.data(), bytes.data() + at, 12);
    at += 12;
    for (const uint32_t i : f) {
      if (i >= n)
        return fail("a face names vertex " + std::to_string(i) + " of " + std::to_string(n));
    }
  }
  for (const auto& [name, range] : header["robots"].items()) {
    const std::optional<RobotId> robot = RobotId::parse(name);
    if (!robot || !range.is_array() || range.size() != 4)
      return fail("robots." + name + " is not a robot's [v_start, v, f_start, f]");
    const uint64_t start = range[0].get<uint64_t>(), count = range[1].get<uint64_t>();
    if (start + count > n) return fail("robots." + name + " runs past the vertices");
    for (uint64_t i = start; i < start + count; ++i) mesh.vertices[i].robot = *robot;
  }
  if (seq != nullptr) *seq = header.value("seq", uint64_t{0});
  return mesh;
}

}  // namespace hydra_multi::web
