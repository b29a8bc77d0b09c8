#pragma once
// What robot updates cost on the wire (the paper's Fig. 9b): per robot and update, the bytes of
// its message, split by what the update carries (io::RobotUpdateBytes), and what the same update
// would have cost as a full resend: the robot's whole map at that moment, the snapshot of every
// update so far (dsg/robot_stream.h), as the paper's robots send it. Each robot's updates are
// taken in sequence order; an update its map cannot take (one after a gap) has no full-resend
// figure until the next snapshot.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/robot_stream.h"

namespace hydra_multi {

struct UpdateBandwidth {
  RobotId robot;
  uint64_t sequence = 0;
  int64_t time_ns = 0;
  bool snapshot = false;
  size_t wire_bytes = 0;       ///< its message as it came: the payload (compressed or not), framing
  size_t record_bytes = 0;     ///< its message uncompressed: the record and the framing
  io::RobotUpdateBytes parts;  ///< of the record
  /// The same moment as a full resend (the whole map uncompressed, with the same framing); none
  /// after a gap.
  std::optional<size_t> full_resend_bytes;
};

struct RobotBandwidth {
  size_t updates = 0;
  size_t wire_bytes = 0;
  size_t record_bytes = 0;
  size_t full_resend_bytes = 0;  ///< of the updates that have the figure
  size_t without_full_resend = 0;
};

class BandwidthLedger {
 public:
  /// `framing_bytes`: what a message adds to its payload (the protocol's header).
  explicit BandwidthLedger(size_t framing_bytes = 0) : framing_bytes_(framing_bytes) {}
  /// One update the station holds (any order; a robot's are taken in sequence order by rows());
  /// `wire_bytes`: of the message it came in (0: its record and the framing).
  void add(const RobotUpdate& update, size_t wire_bytes = 0);
  /// Every update, by robot, then sequence (a snapshot after the delta of its sequence).
  std::vector<UpdateBandwidth> rows() const;

 private:
  std::vector<UpdateBandwidth> robotRows(
      RobotId robot, const std::vector<std::pair<RobotUpdate, size_t>>& arrived) const;

  size_t framing_bytes_;
  std::map<RobotId, std::vector<std::pair<RobotUpdate, size_t>>> updates_;
};

/// The rows added up per robot.
std::map<RobotId, RobotBandwidth> bandwidthTotals(const std::vector<UpdateBandwidth>& rows);
/// Every robot's added up.
RobotBandwidth teamBandwidth(const std::map<RobotId, RobotBandwidth>& robots);
/// Like for like: full resends over the same updates uncompressed (0 without updates).
double fullResendRatio(const RobotBandwidth& totals);

/// One line per update: robot, sequence, time, kind, wire and record bytes, the parts, full
/// resend.
std::string bandwidthCsv(const std::vector<UpdateBandwidth>& rows);
/// Cumulative MB per robot against robot time, log scale: our updates (solid), the same on the
/// wire when they came compressed (dotted), full resends (dashed).
std::string bandwidthSvg(const std::vector<UpdateBandwidth>& rows);

}  // namespace hydra_multi
