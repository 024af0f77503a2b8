// The web review (`leafdig server web`, docs/web.md): the lab server's sessions for curators
// and readers in any browser, and the JSON API its pages use. It holds no password and no
// role of its own: a login is a connection to the lab server opened with the login's own
// password (the server checks it), kept for that browser's session and used for each of its
// requests, so the server's row-level security and role limits stay the only authority.
// Routing, sessions, CSRF and rate limits here; HTTP in http.cpp; the JSON of a session is
// `sessions show --json`'s (sessions_show.hpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "http.hpp"

namespace leafdig::cli::web {

struct WebOptions {
  // postgresql://HOST[:PORT]/DATABASE[?sslmode=…]: where the logins connect (a user or
  // password in it is ignored: each login brings its own).
  std::string serverUrl;
  std::chrono::seconds idle{std::chrono::minutes(30)};   // a browser session unused this long ends
  std::chrono::seconds longest{std::chrono::hours(12)};  // and every one ends this long after its login
  bool secureCookie = false;                             // behind a TLS proxy: the cookie only over https
  int failedLoginsAllowed = 5;                           // per login and per address, in the window
  std::chrono::seconds failedLoginWindow{std::chrono::minutes(5)};
  // Every refused login answers after this long from its request, whatever refused it (an
  // unknown login and a wrong password are told apart neither by words nor by time).
  std::chrono::milliseconds refusedLoginTime{800};
  int sessionsPerLogin = 4;  // a login's fifth browser session ends its oldest (each holds a connection)
};

class WebApp {
 public:
  explicit WebApp(WebOptions options);
  ~WebApp();
  WebApp(const WebApp&) = delete;
  WebApp& operator=(const WebApp&) = delete;

  // Answers one request (any thread).
  HttpResponse handle(const HttpRequest& request);

 private:
  struct Session;
  struct Call;
  HttpResponse route(const HttpRequest& request);
  HttpResponse login(const HttpRequest& request);
  HttpResponse logout(const HttpRequest& request);
  HttpResponse api(const HttpRequest& request, Call& call);
  std::shared_ptr<Session> sessionOf(const HttpRequest& request);
  bool throttled(const std::string& login, const std::string& address);
  void failedLogin(const std::string& login, const std::string& address);

  WebOptions options_;
  std::mutex mutex_;  // guards sessions_ and failures_
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::map<std::string, std::vector<std::chrono::steady_clock::time_point>> failures_;
};

// The login's URL: the server's with the login and password put in (percent-encoded) and
// no password file consulted. Throws std::invalid_argument when serverUrl is not postgresql://.
[[nodiscard]] std::string loginUrl(const std::string& serverUrl, const std::string& login, const std::string& password);

}  // namespace leafdig::cli::web
