#pragma once
// Spark-DSG's attribute records (../shared/reference/spark-dsg-wire.md §1.5, §1.7): the type id
// into the message's names table, the metadata (from 1.0.6), then the fields of the type and of the
// types it derives from, in their order and in the layout of the message's version. Internal to
// dsg/io (spark_binary.cpp reads and writes nodes and edges with them).

#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/dsg/io/spark_wire.h"

namespace hydra_multi::io::spark {

/// The attribute types this codec reads and writes.
enum class Kind { kNode, kSemantic, kObject, kRoom, kPlace, kPlace2d, kAgent, kEdge };

/// The kind of each name of a names table (nullopt: a type this codec does not read).
std::vector<std::optional<Kind>> kindsOf(const std::vector<std::string>& names);

/// An attribute record; the type id must name a kind in `kinds` (`types` names it in errors).
void readAttributes(Reader& r, const std::vector<std::string>& types,
                    const std::vector<std::optional<Kind>>& kinds, Version v, uint8_t& type_id,
                    Attributes& a);
/// Throws std::invalid_argument when the type id names no known type (the caller's bug).
void writeAttributes(Writer& w, const std::vector<std::string>& types, uint8_t type_id,
                     const Attributes& a, Version v);

}  // namespace hydra_multi::io::spark
