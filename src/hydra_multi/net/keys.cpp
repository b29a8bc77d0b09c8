#include "hydra_multi/net/keys.h"

#include <sys/stat.h>

#include <zmq.h>
#include <filesystem>
#include <fstream>

#include "hydra_multi/dsg/io/graph_file.h"

namespace hydra_multi::net {
namespace {

bool isZ85Key(const std::string& key) {
  static const std::string kAlphabet =
      "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ.-:+=^!/*?&<>()[]{}@%$#";
  if (key.size() != 40) return false;
  for (const char c : key)
    if (kAlphabet.find(c) == std::string::npos) return false;
  uint8_t decoded[32];
  return zmq_z85_decode(decoded, key.c_str()) != nullptr;
}

}  // namespace

bool curveAvailable() { return zmq_has("curve") != 0; }

Result<KeyPair> generateKeyPair() {
  if (!curveAvailable()) return Error{"this ZeroMQ library has no CURVE (built without libsodium)"};
  char public_key[41], secret_key[41];
  if (zmq_curve_keypair(public_key, secret_key) != 0)
    return Error{std::string("cannot make a CURVE key pair: ") + zmq_strerror(zmq_errno())};
  return KeyPair{public_key, secret_key};
}

Result<std::string> publicKeyOf(const std::string& secret_z85) {
  if (!isZ85Key(secret_z85)) return Error{"not a Z85 key of 40 characters"};
  char public_key[41];
  if (zmq_curve_public(public_key, secret_z85.c_str()) != 0)
    return Error{std::string("cannot derive the public key: ") + zmq_strerror(zmq_errno())};
  return std::string(public_key);
}

Status writeKeyPair(const std::string& prefix, const KeyPair& keys) {
  namespace fs = std::filesystem;
  const std::string secret = prefix + ".key", pub = prefix + ".pub";
  for (const std::string& path : {secret, pub}) {
    if (fs::exists(path)) return Error{path + ": exists already; not overwriting a key"};
  }
  {
    std::ofstream out(secret);
    if (!out) return Error{secret + ": cannot write"};
  }
  ::chmod(secret.c_str(), 0600);  // the secret key is its owner's alone, before it is written
  if (Status s = io::writeFile(secret, keys.secret_z85 + "\n"); !s) return s;
  return io::writeFile(pub, keys.public_z85 + "\n");
}

Result<std::string> readKey(const std::string& path) {
  auto text = io::readFile(path);
  if (!text) return Error{text.error()};
  std::string key = text.value();
  while (!key.empty() && (key.back() == '\n' || key.back() == '\r' || key.back() == ' '))
    key.pop_back();
  if (!isZ85Key(key))
    return Error{path + ": not a CURVE key (one line of 40 Z85 characters, as keygen writes)"};
  return key;
}

Result<std::map<std::string, RobotId>> readRobotKeys(const std::string& dir) {
  namespace fs = std::filesystem;
  std::map<std::string, RobotId> keys;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".pub") continue;
    const std::string name = e.path().stem().string();
    const auto robot = RobotId::parse(name);
    if (!robot)
      return Error{e.path().string() + ": '" + name +
                   "' is not a robot's name (a key file is named by its robot: a.pub, b.pub, ...)"};
    auto key = readKey(e.path().string());
    if (!key) return Error{key.error()};
    const auto [it, added] = keys.emplace(key.value(), *robot);
    if (!added)
      return Error{e.path().string() + ": the same key as robot " + it->second.str() + "'s"};
  }
  if (ec) return Error{dir + ": cannot read the key folder: " + ec.message()};
  if (keys.empty()) return Error{dir + ": no robot key (*.pub) in it"};
  return keys;
}

}  // namespace hydra_multi::net
