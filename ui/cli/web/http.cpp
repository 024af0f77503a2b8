// The one translation unit that includes cpp-httplib (http.hpp says why it is kept here).
#include "http.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace leafdig::cli::web {

namespace {

// httplib listens with a backlog of 5 (CPPHTTPLIB_LISTEN_BACKLOG, fixed when Debian built the
// library): fifty browsers connecting at once overflow it and the kernel drops their SYNs, which
// the clients resend a second later (the web benchmark's p99 was that second). Linux takes a
// second listen() on a listening socket as a new backlog; the socket is the server's protected
// member, so this is the one place that reaches it.
class Server : public httplib::Server {
 public:
  void widenBacklog(int backlog) {
    const socket_t sock = svr_sock_;
    if (sock != INVALID_SOCKET) (void)::listen(sock, backlog);
  }
};

}  // namespace

struct HttpServer::Impl {
  Server server;
  HttpHandler handler;
};

namespace {

HttpRequest toRequest(const httplib::Request& r) {
  HttpRequest out;
  out.method = r.method;
  out.path = r.path;
  out.body = r.body;
  out.remoteAddress = r.remote_addr;
  for (const auto& [k, v] : r.params) out.query[k] = v;
  for (const auto& [k, v] : r.headers) {
    std::string name = k;
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    out.headers[name] = v;
  }
  return out;
}

void fromResponse(const HttpResponse& from, httplib::Response& to) {
  to.status = from.status;
  for (const auto& [k, v] : from.headers) to.set_header(k, v);
  to.set_content(from.body, from.contentType);
}

}  // namespace

HttpServer::HttpServer(HttpHandler handler, HttpLimits limits) : impl_(std::make_unique<Impl>()) {
  impl_->handler = std::move(handler);
  auto& s = impl_->server;
  s.set_payload_max_length(limits.maxBodyBytes);
  s.set_read_timeout(limits.readTimeoutSeconds, 0);
  s.set_write_timeout(limits.readTimeoutSeconds, 0);
  s.set_keep_alive_timeout(limits.keepAliveSeconds);
  s.set_keep_alive_max_count(100);
  const auto threads = static_cast<std::size_t>(std::max(1, limits.threads));
  s.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  const auto serve = [this](const httplib::Request& req, httplib::Response& res) {
    fromResponse(impl_->handler(toRequest(req)), res);
  };
  s.Get(R"(/.*)", serve);
  s.Post(R"(/.*)", serve);
  // Any other method, and a request httplib could not take (too large, malformed), is answered
  // in the API's own shape; nothing of httplib's own pages reaches a browser.
  s.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    // Debian's httplib compresses an answer with brotli when the browser takes it (every browser
    // does), at brotli's slowest quality: 0.9 s for three.js's 670 kB module, seconds for a list
    // of 10 000 sessions. gzip does the same file in 20 ms to 25 % of its size, so the browser is
    // offered gzip only. The request is httplib's own non-const object, handed over as const.
    auto& headers = const_cast<httplib::Request&>(req).headers;  // NOLINT(cppcoreguidelines-pro-type-const-cast)
    const std::string accepted = req.get_header_value("Accept-Encoding");
    headers.erase("Accept-Encoding");
    if (accepted.find("gzip") != std::string::npos) headers.emplace("Accept-Encoding", "gzip");
    if (req.method == "GET" || req.method == "POST" || req.method == "HEAD")
      return httplib::Server::HandlerResponse::Unhandled;
    res.status = 405;
    res.set_header("Allow", "GET, POST");
    res.set_content(R"({"error":"method not allowed","what_to_do":"use GET to read and POST to change"})",
                    "application/json");
    return httplib::Server::HandlerResponse::Handled;
  });
  s.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string what = res.status == 413   ? "the request is too large"
                             : res.status == 404 ? "no such page"
                                                 : "the request could not be read";
    res.set_content(R"({"error":")" + what + R"(","what_to_do":"check the address and the request's body"})",
                    "application/json");
  });
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, const std::exception_ptr&) {
    res.status = 500;
    res.set_content(
        R"({"error":"the server failed on this request","what_to_do":"try again; if it persists, see the web server's log"})",
        "application/json");
  });
}

HttpServer::~HttpServer() = default;

int HttpServer::bind(const std::string& host, int port) {
  const int bound =
      port == 0 ? impl_->server.bind_to_any_port(host) : (impl_->server.bind_to_port(host, port) ? port : -1);
  if (bound < 0)
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) +
                             " (in use, or not an address of this machine)");
  impl_->server.widenBacklog(SOMAXCONN);
  return bound;
}

void HttpServer::run() {
  (void)impl_->server.listen_after_bind();
}

void HttpServer::stop() {
  impl_->server.stop();
}

}  // namespace leafdig::cli::web
