#pragma once
// zmq::poll that a signal may interrupt (EINTR: SIGINT or SIGTERM, the station's stop): false
// then, instead of the exception cppzmq throws; any other error still throws. Inside net only.

#include <cerrno>
#include <chrono>
#include <zmq.hpp>

namespace hydra_multi::net {

inline bool interruptiblePoll(zmq::pollitem_t* items, size_t count,
                              std::chrono::milliseconds timeout) {
  try {
    zmq::poll(items, count, timeout);
    return true;
  } catch (const zmq::error_t& e) {
    if (e.num() == EINTR) return false;
    throw;
  }
}

}  // namespace hydra_multi::net
