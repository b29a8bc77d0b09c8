#pragma once
// Typed access to parsed JSON, shared by our JSON format and the Spark-DSG importer. Every accessor
// throws DecodeError naming the key and what it expected; the readers add the item ("nodes[12]"),
// so a message reads "nodes[12]: key 'position': expected an array of 3 numbers".

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "hydra_multi/core/node_id.h"
#include "hydra_multi/dsg/io/decode_error.h"

namespace hydra_multi::io {

using Json = nlohmann::ordered_json;

/// The member `key` of an object; throws when `j` is not an object or has no such key.
const Json& member(const Json& j, const char* key);
bool hasMember(const Json& j, const char* key);

/// While one lives (in this thread), records every key the decoders look up (member, hasMember),
/// so that a reader can say what of a document it did not read.
class KeyUse {
 public:
  KeyUse();
  ~KeyUse();
  KeyUse(const KeyUse&) = delete;
  KeyUse& operator=(const KeyUse&) = delete;
  void note(const Json& object, const char* key) { read_[&object].insert(key); }
  /// The keys of `root` never looked up, each as a path with "[]" for array elements
  /// ("nodes[].attributes.mesh_connections") and how often it occurs. Keys under an unread key
  /// are not listed.
  std::map<std::string, size_t> unread(const Json& root) const;
  /// "3 keys not read: nodes[].attributes.color (7 times), ..." (empty when all were read).
  static std::string describe(const std::map<std::string, size_t>& unread);

 private:
  void walk(const Json& j, const std::string& path, std::map<std::string, size_t>& out) const;
  std::unordered_map<const Json*, std::set<std::string>> read_;
  KeyUse* previous_ = nullptr;
};

double toDouble(const Json& j, const char* key);
float toFloat(const Json& j, const char* key);
int64_t toInt64(const Json& j, const char* key);
uint64_t toUint64(const Json& j, const char* key);
uint32_t toUint32(const Json& j, const char* key);
uint8_t toUint8(const Json& j, const char* key);
bool toBool(const Json& j, const char* key);
std::string toString(const Json& j, const char* key);
/// An array of exactly n numbers.
std::vector<double> toNumbers(const Json& j, const char* key, size_t n);
Eigen::Vector3d toVector3d(const Json& j, const char* key);
Eigen::Vector3f toVector3f(const Json& j, const char* key);
/// A node id in readable form ("O(3)", "a12", "O(3)@b").
NodeId toNodeId(const Json& j, const char* key);
/// The array `j`; throws when it is not one.
const Json& toArray(const Json& j, const char* key);

/// The double whose shortest decimal form reads back as exactly `value` when parsed as a double and
/// rounded to float: readable floats in JSON ("0.1", not "0.10000000149011612") that round-trip.
double floatForJson(float value);

/// Readable layout for documents with long arrays: the top-level keys (and those of nested objects)
/// one per line, each element of an array of objects or arrays compact on a line of its own.
std::string dumpOneItemPerLine(const Json& root);

/// Applies `read` to each element of the array `items`, naming the element in errors
/// ("<name>[<i>]: ...").
template <typename ReadItem>
auto readArray(const Json& items, const char* name, ReadItem read) {
  const Json& array = toArray(items, name);
  std::vector<decltype(read(array.front()))> result;
  result.reserve(array.size());
  for (size_t i = 0; i < array.size(); ++i) {
    try {
      result.push_back(read(array[i]));
    } catch (const DecodeError& error) {
      throw error.within(std::string(name) + "[" + std::to_string(i) + "]");
    } catch (const nlohmann::json::exception& error) {
      throw DecodeError(std::string(name) + "[" + std::to_string(i) + "]: " + error.what());
    }
  }
  return result;
}

}  // namespace hydra_multi::io
