#include "hydra_multi/dsg/io/json_fields.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace hydra_multi::io {
namespace {

[[noreturn]] void expected(const char* key, const std::string& what, const Json& got) {
  throw DecodeError(std::string("key '") + key + "': expected " + what + ", got " +
                    std::string(got.type_name()));
}

thread_local KeyUse* key_use = nullptr;

}  // namespace

KeyUse::KeyUse() : previous_(key_use) { key_use = this; }
KeyUse::~KeyUse() { key_use = previous_; }

void KeyUse::walk(const Json& j, const std::string& path,
                  std::map<std::string, size_t>& out) const {
  if (j.is_array()) {
    for (const Json& element : j) walk(element, path + "[]", out);
    return;
  }
  if (!j.is_object()) return;
  const auto read = read_.find(&j);
  for (const auto& [key, value] : j.items()) {
    const std::string at = path.empty() ? key : path + "." + key;
    if (read == read_.end() || !read->second.count(key))
      ++out[at];
    else
      walk(value, at, out);
  }
}

std::map<std::string, size_t> KeyUse::unread(const Json& root) const {
  std::map<std::string, size_t> out;
  walk(root, "", out);
  return out;
}

std::string KeyUse::describe(const std::map<std::string, size_t>& unread) {
  if (unread.empty()) return "";
  std::string text =
      std::to_string(unread.size()) + (unread.size() == 1 ? " key not read: " : " keys not read: ");
  size_t shown = 0;
  for (const auto& [path, count] : unread) {
    if (shown++ == 8) {
      text += ", ...";
      break;
    }
    text += (shown > 1 ? ", " : "") + path +
            (count > 1 ? " (" + std::to_string(count) + " times)" : std::string());
  }
  return text;
}

const Json& member(const Json& j, const char* key) {
  if (key_use) key_use->note(j, key);
  if (!j.is_object())
    throw DecodeError(std::string("expected an object holding key '") + key + "'");
  const auto it = j.find(key);
  if (it == j.end()) throw DecodeError(std::string("missing key '") + key + "'");
  return *it;
}

bool hasMember(const Json& j, const char* key) {
  if (key_use) key_use->note(j, key);
  return j.is_object() && j.contains(key);
}

double toDouble(const Json& j, const char* key) {
  if (!j.is_number()) expected(key, "a number", j);
  return j.get<double>();
}

float toFloat(const Json& j, const char* key) {
  const double v = toDouble(j, key);
  if (std::isfinite(v) && std::abs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
    throw DecodeError(std::string("key '") + key + "': " + std::to_string(v) +
                      " does not fit in a float");
  }
  return static_cast<float>(v);
}

int64_t toInt64(const Json& j, const char* key) {
  if (j.is_number_unsigned()) {
    if (j.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
      throw DecodeError(std::string("key '") + key + "': integer too large");
    }
    return static_cast<int64_t>(j.get<uint64_t>());
  }
  if (!j.is_number_integer()) expected(key, "an integer", j);
  return j.get<int64_t>();
}

uint64_t toUint64(const Json& j, const char* key) {
  if (j.is_number_unsigned()) return j.get<uint64_t>();
  if (j.is_number_integer() && j.get<int64_t>() >= 0)
    return static_cast<uint64_t>(j.get<int64_t>());
  expected(key, "a non-negative integer", j);
}

uint32_t toUint32(const Json& j, const char* key) {
  const uint64_t v = toUint64(j, key);
  if (v > std::numeric_limits<uint32_t>::max()) {
    throw DecodeError(std::string("key '") + key + "': " + std::to_string(v) +
                      " does not fit in 32 bits");
  }
  return static_cast<uint32_t>(v);
}

uint8_t toUint8(const Json& j, const char* key) {
  const uint64_t v = toUint64(j, key);
  if (v > 255) throw DecodeError(std::string("key '") + key + "': " + std::to_string(v) + " > 255");
  return static_cast<uint8_t>(v);
}

bool toBool(const Json& j, const char* key) {
  if (!j.is_boolean()) expected(key, "true or false", j);
  return j.get<bool>();
}

std::string toString(const Json& j, const char* key) {
  if (!j.is_string()) expected(key, "a string", j);
  return j.get<std::string>();
}

std::vector<double> toNumbers(const Json& j, const char* key, size_t n) {
  const std::string what = "an array of " + std::to_string(n) + " numbers";
  if (!j.is_array() || j.size() != n) expected(key, what, j);
  std::vector<double> values(n);
  for (size_t i = 0; i < n; ++i) {
    if (!j[i].is_number()) expected(key, what, j);
    values[i] = j[i].get<double>();
  }
  return values;
}

Eigen::Vector3d toVector3d(const Json& j, const char* key) {
  const auto v = toNumbers(j, key, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector3f toVector3f(const Json& j, const char* key) {
  const auto v = toNumbers(j, key, 3);
  Eigen::Vector3f result;
  for (int i = 0; i < 3; ++i) result[i] = toFloat(Json(v[static_cast<size_t>(i)]), key);
  return result;
}

NodeId toNodeId(const Json& j, const char* key) {
  const std::string text = toString(j, key);
  const auto id = NodeId::parse(text);
  if (!id) throw DecodeError(std::string("key '") + key + "': '" + text + "' is not a node id");
  return *id;
}

const Json& toArray(const Json& j, const char* key) {
  if (!j.is_array()) expected(key, "an array", j);
  return j;
}

namespace {

void dumpItem(const Json& value, const std::string& indent, std::string& out) {
  const bool long_array =
      value.is_array() && !value.empty() && (value.front().is_object() || value.front().is_array());
  if (value.is_object() && !value.empty()) {
    out += "{\n";
    size_t i = 0;
    for (auto it = value.begin(); it != value.end(); ++it, ++i) {
      out += indent + "  " + Json(it.key()).dump() + ": ";
      dumpItem(it.value(), indent + "  ", out);
      out += i + 1 < value.size() ? ",\n" : "\n";
    }
    out += indent + "}";
  } else if (long_array) {
    out += "[\n";
    for (size_t i = 0; i < value.size(); ++i) {
      out += indent + "  " + value[i].dump();
      out += i + 1 < value.size() ? ",\n" : "\n";
    }
    out += indent + "]";
  } else {
    out += value.dump();
  }
}

}  // namespace

std::string dumpOneItemPerLine(const Json& root) {
  std::string out;
  dumpItem(root, "", out);
  return out + "\n";
}

double floatForJson(float value) {
  if (!std::isfinite(value)) return static_cast<double>(value);
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (ec == std::errc()) {
    *end = '\0';
    const double shortest = std::strtod(buffer, nullptr);
    if (static_cast<float>(shortest) == value) return shortest;
  }
  return static_cast<double>(value);  // exact, if long
}

}  // namespace hydra_multi::io
