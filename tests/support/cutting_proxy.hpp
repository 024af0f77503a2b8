// A TCP proxy on 127.0.0.1 that forwards to a server and cuts every connection once the
// client has sent more than `cutAfterBytes` (a dropped network in the middle of a
// transaction, as a flaky field link does). 0: never cuts.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace leafdig::test {

class CuttingProxy {
 public:
  CuttingProxy(int serverPort, std::size_t cutAfterBytes) : server_(serverPort), cutAfter_(cutAfterBytes) {
    listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(listener_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t n = sizeof a;
    ::getsockname(listener_, reinterpret_cast<sockaddr*>(&a), &n);
    port_ = ntohs(a.sin_port);
    ::listen(listener_, 8);
    thread_ = std::thread([this] { run(); });
  }
  CuttingProxy(const CuttingProxy&) = delete;
  CuttingProxy& operator=(const CuttingProxy&) = delete;
  ~CuttingProxy() {
    stop_ = true;
    thread_.join();
    ::close(listener_);
  }
  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] int cuts() const { return cuts_; }

 private:
  void run() {
    while (!stop_) {
      pollfd p{listener_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      const int client = ::accept(listener_, nullptr, nullptr);
      if (client < 0) continue;
      const int upstream = ::socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      a.sin_port = htons(static_cast<std::uint16_t>(server_));
      if (::connect(upstream, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        ::close(client);
        ::close(upstream);
        continue;
      }
      forward(client, upstream);  // one connection at a time: enough for a push
      ::close(client);
      ::close(upstream);
    }
  }
  void forward(int client, int upstream) {
    std::size_t sent = 0;
    std::vector<char> buffer(1 << 16);
    while (!stop_) {
      pollfd p[2] = {{client, POLLIN, 0}, {upstream, POLLIN, 0}};
      if (::poll(p, 2, 50) <= 0) continue;
      for (int k = 0; k < 2; ++k) {
        if ((p[k].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
        const ssize_t n = ::read(p[k].fd, buffer.data(), buffer.size());
        if (n <= 0) return;
        if (k == 0) {
          sent += static_cast<std::size_t>(n);
          if (cutAfter_ > 0 && sent > cutAfter_) {
            ++cuts_;
            return;  // the bytes that crossed the limit never reach the server
          }
        }
        const int to = k == 0 ? upstream : client;
        for (ssize_t done = 0; done < n;) {
          const ssize_t w = ::write(to, buffer.data() + done, static_cast<std::size_t>(n - done));
          if (w <= 0) return;
          done += w;
        }
      }
    }
  }

  int server_;
  std::size_t cutAfter_;
  int listener_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> cuts_{0};
  std::thread thread_;
};

}  // namespace leafdig::test
