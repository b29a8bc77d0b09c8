#pragma once
// CURVE keys (ZeroMQ's CurveZMQ) for robots and the station, in files of one Z85 line each:
// NAME.key holds the secret key, NAME.pub the public one (`hydra-multi keygen`). The station
// admits the robots whose public keys lie in its key folder, each file named by its robot
// (a.pub, b.pub, ...), and a robot's connection speaks only for the robot of its key.

#include <map>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/robot_id.h"

namespace hydra_multi::net {

/// Whether the ZeroMQ library was built with CURVE (libsodium).
bool curveAvailable();

struct KeyPair {
  std::string public_z85, secret_z85;  ///< 40 characters each
};
Result<KeyPair> generateKeyPair();
/// The public key of a secret one.
Result<std::string> publicKeyOf(const std::string& secret_z85);

/// Writes PREFIX.key (read-write for its owner only) and PREFIX.pub; refuses to overwrite either.
Status writeKeyPair(const std::string& prefix, const KeyPair& keys);
/// A key file's key: one line of 40 Z85 characters; an error names the file.
Result<std::string> readKey(const std::string& path);
/// Every *.pub of `dir`, public key -> robot (the file's name); an error names the file that is
/// not a robot's key, or a key that two robots share.
Result<std::map<std::string, RobotId>> readRobotKeys(const std::string& dir);

}  // namespace hydra_multi::net
