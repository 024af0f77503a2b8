// The web review's HTTP: a request in, a response out, and a server that runs a handler for
// each request on a pool of threads. cpp-httplib (Debian's libcpp-httplib-dev, built as a
// shared library) underneath, included by http.cpp alone: nothing else of leafdig sees it.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace leafdig::cli::web {

struct HttpRequest {
  std::string method, path, body, remoteAddress;
  std::map<std::string, std::string> query;    // the query string's parameters, decoded
  std::map<std::string, std::string> headers;  // names in lower case; a repeated header: its last value
  [[nodiscard]] std::string header(const std::string& lowerCaseName) const {
    const auto it = headers.find(lowerCaseName);
    return it == headers.end() ? std::string() : it->second;
  }
};

struct HttpResponse {
  int status = 200;
  std::string contentType = "application/json", body;
  std::vector<std::pair<std::string, std::string>> headers;
};

using HttpHandler = std::function<HttpResponse(const HttpRequest&)>;

struct HttpLimits {
  std::size_t maxBodyBytes = 1 << 20;  // a larger request body is refused (413) unread
  // Connections served at once: httplib gives each open connection a thread while it is kept
  // alive, so this is how many browsers (up to six connections each) and scripts are answered
  // without waiting for another's connection to close (docs/benchmarks.md, the web review).
  int threads = 96;
  int keepAliveSeconds = 2;     // an idle kept-alive connection gives its thread back after this
  int readTimeoutSeconds = 10;  // a client that stalls mid-request is dropped
};

class HttpServer {
 public:
  HttpServer(HttpHandler handler, HttpLimits limits = {});
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds host:port (port 0: any free one) and returns the port bound; throws
  // std::runtime_error naming the address when it cannot.
  int bind(const std::string& host, int port);
  // Serves until stop() (from another thread or a signal's watcher).
  void run();
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace leafdig::cli::web
