// A TCP proxy for the network fault tests: every connection it accepts is forwarded to the
// upstream address with each chunk of bytes held back `--delay-ms` in both directions, and is cut
// (both sides closed) at a random moment, exponentially distributed with mean `--cut-mean-s`
// after it opened (seeded: `--seed`). It writes the port it listens on to `--port-file`, runs
// until SIGTERM or SIGINT, then prints what it did on one line. Test tooling only.
//
//   fault_proxy --listen 127.0.0.1:0 --upstream 10.0.0.1:7800 --port-file F [--delay-ms 50]
//               [--cut-mean-s 2] [--seed 1]

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <list>
#include <random>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t stop = 0;
extern "C" void onSignal(int) { stop = 1; }

struct Address {
  sockaddr_in sa{};
};

bool parseAddress(const std::string& text, Address& out) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) return false;
  out.sa.sin_family = AF_INET;
  out.sa.sin_port = htons(static_cast<uint16_t>(std::atoi(text.c_str() + colon + 1)));
  return inet_pton(AF_INET, text.substr(0, colon).c_str(), &out.sa.sin_addr) == 1;
}

void nonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK); }

struct Chunk {
  Clock::time_point due;
  std::string bytes;
};

// One accepted connection and its upstream: bytes read from one side wait in the other's queue.
struct Link {
  int fd[2] = {-1, -1};  // 0: the client, 1: upstream
  std::deque<Chunk> to[2];
  Clock::time_point cut_at;
  bool open = true;
  void close() {
    for (int& f : fd) {
      if (f >= 0) ::close(f);
      f = -1;
    }
    open = false;
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string listen_text, upstream_text, port_file;
  double delay_ms = 50.0, cut_mean_s = 2.0;
  unsigned seed = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--listen")
      listen_text = value;
    else if (key == "--upstream")
      upstream_text = value;
    else if (key == "--port-file")
      port_file = value;
    else if (key == "--delay-ms")
      delay_ms = std::atof(value.c_str());
    else if (key == "--cut-mean-s")
      cut_mean_s = std::atof(value.c_str());
    else if (key == "--seed")
      seed = static_cast<unsigned>(std::atoi(value.c_str()));
  }
  Address listen_at, upstream;
  if (!parseAddress(listen_text, listen_at) || !parseAddress(upstream_text, upstream) ||
      port_file.empty()) {
    std::fprintf(stderr, "usage: fault_proxy --listen IP:PORT --upstream IP:PORT --port-file F\n");
    return 2;
  }
  // No SA_RESTART: a signal ends a blocking connect() too.
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
  const int server = socket(AF_INET, SOCK_STREAM, 0);
  const int yes = 1;
  setsockopt(server, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  if (bind(server, reinterpret_cast<sockaddr*>(&listen_at.sa), sizeof listen_at.sa) != 0 ||
      listen(server, 16) != 0) {
    std::fprintf(stderr, "fault_proxy: cannot listen on %s: %s\n", listen_text.c_str(),
                 std::strerror(errno));
    return 1;
  }
  sockaddr_in bound{};
  socklen_t bound_size = sizeof bound;
  getsockname(server, reinterpret_cast<sockaddr*>(&bound), &bound_size);
  std::ofstream(port_file) << ntohs(bound.sin_port) << "\n";
  nonBlocking(server);

  std::mt19937 rng(seed);
  std::exponential_distribution<double> cut_after(1.0 / cut_mean_s);
  const auto delay = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double, std::milli>(delay_ms));
  std::list<Link> links;
  size_t accepted = 0, cuts = 0, bytes = 0, refused_upstream = 0;
  std::vector<char> buffer(1 << 16);
  while (!stop) {
    std::vector<pollfd> fds = {{server, POLLIN, 0}};
    std::vector<std::pair<Link*, int>> owners = {{nullptr, 0}};
    Clock::time_point wake = Clock::now() + std::chrono::milliseconds(50);
    for (Link& link : links) {
      wake = std::min(wake, link.cut_at);
      for (int side = 0; side < 2; ++side) {
        short events = POLLIN;
        if (!link.to[side].empty()) {
          if (link.to[side].front().due <= Clock::now())
            events |= POLLOUT;
          else
            wake = std::min(wake, link.to[side].front().due);
        }
        fds.push_back({link.fd[side], events, 0});
        owners.emplace_back(&link, side);
      }
    }
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(wake - Clock::now());
    poll(fds.data(), fds.size(), static_cast<int>(std::max<int64_t>(0, wait.count()) + 1));
    if (fds[0].revents & POLLIN) {
      const int client = accept(server, nullptr, nullptr);
      if (client >= 0) {
        const int up = socket(AF_INET, SOCK_STREAM, 0);
        const timeval connect_timeout{2, 0};  // the upstream gone: give up after 2 s
        setsockopt(up, SOL_SOCKET, SO_SNDTIMEO, &connect_timeout, sizeof connect_timeout);
        if (connect(up, reinterpret_cast<sockaddr*>(&upstream.sa), sizeof upstream.sa) != 0) {
          ++refused_upstream;
          ::close(up);
          ::close(client);
        } else {
          ++accepted;
          for (const int f : {client, up}) {
            nonBlocking(f);
            setsockopt(f, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
          }
          Link link;
          link.fd[0] = client;
          link.fd[1] = up;
          link.cut_at = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(cut_after(rng)));
          links.push_back(std::move(link));
        }
      }
    }
    for (size_t i = 1; i < fds.size(); ++i) {
      auto [link, side] = owners[i];
      if (!link->open) continue;
      if (fds[i].revents & (POLLIN | POLLHUP | POLLERR)) {
        const ssize_t n = read(link->fd[side], buffer.data(), buffer.size());
        if (n <= 0) {
          link->close();
          continue;
        }
        bytes += static_cast<size_t>(n);
        link->to[1 - side].push_back({Clock::now() + delay, std::string(buffer.data(), n)});
      }
      if (fds[i].revents & POLLOUT) {
        std::deque<Chunk>& queue = link->to[side];
        while (!queue.empty() && queue.front().due <= Clock::now()) {
          const ssize_t n =
              write(link->fd[side], queue.front().bytes.data(), queue.front().bytes.size());
          if (n < 0) break;  // full: later
          queue.front().bytes.erase(0, static_cast<size_t>(n));
          if (!queue.front().bytes.empty()) break;
          queue.pop_front();
        }
      }
    }
    for (Link& link : links) {
      if (link.open && Clock::now() >= link.cut_at) {
        ++cuts;
        link.close();
      }
    }
    links.remove_if([](const Link& link) { return !link.open; });
  }
  std::printf(
      "fault_proxy: %zu connections, %zu cut, %zu bytes forwarded, %zu not connected "
      "upstream\n",
      accepted, cuts, bytes, refused_upstream);
  return 0;
}
