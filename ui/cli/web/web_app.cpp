#include "web_app.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <thread>
#include <variant>

#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/model/errors.hpp"
#include "session_api.hpp"
#include "sessions_show.hpp"
#include "web_assets.hpp"

namespace leafdig::cli::web {

namespace acq = leafdig::acquisition;
using namespace detail;  // the API's answers and one session's endpoints (session_api.hpp)
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct WebApp::Session {
  std::string login, csrf;
  db::LabRole role = db::LabRole::Reader;
  std::unique_ptr<db::LabStore> store;  // the login's own connection
  std::mutex use;                       // one request at a time on it
  Clock::time_point created, lastUsed;  // lastUsed under WebApp::mutex_
};

// What one request carries through the API: its browser session (none before a login).
struct WebApp::Call {
  std::shared_ptr<Session> session;
};

namespace {

constexpr const char* kCookie = "leafdig_session";
constexpr std::size_t kLongestLogin = 63;  // PostgreSQL's NAMEDATALEN - 1
constexpr std::size_t kLongestPassword = 1024;

// Every answer, page or API: nothing inline, nothing from another origin, never in a frame.
constexpr std::array<std::pair<const char*, const char*>, 7> kSecurityHeaders{
    {{"Content-Security-Policy",
      "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; connect-src 'self'; "
      "base-uri 'none'; form-action 'self'; frame-ancestors 'none'"},
     {"X-Content-Type-Options", "nosniff"},
     {"Referrer-Policy", "no-referrer"},
     {"X-Frame-Options", "DENY"},
     {"Cache-Control", "no-store"},
     {"Cross-Origin-Opener-Policy", "same-origin"},
     {"Cross-Origin-Resource-Policy", "same-origin"}}};

std::string randomToken() {
  unsigned char bytes[32];
  std::ifstream urandom("/dev/urandom", std::ios::binary);
  if (!urandom.read(reinterpret_cast<char*>(bytes), sizeof bytes))
    throw std::runtime_error("cannot read /dev/urandom for a session token");
  std::string out;
  out.reserve(2 * sizeof bytes);
  for (unsigned char b : bytes) {
    char hex[3];
    std::snprintf(hex, sizeof hex, "%02x", b);
    out += hex;
  }
  return out;
}

// Equal strings compared in a time that does not depend on where they differ.
bool sameSecret(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i)
    diff |= static_cast<unsigned char>((i < a.size() ? a[i] : 0) ^ (i < b.size() ? b[i] : 0));
  return diff == 0;
}

std::string cookieValue(const std::string& header, const std::string& name) {
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(';', at);
    if (end == std::string::npos) end = header.size();
    std::string part = header.substr(at, end - at);
    const std::size_t first = part.find_first_not_of(' ');
    part = first == std::string::npos ? std::string() : part.substr(first);
    if (part.rfind(name + "=", 0) == 0) return part.substr(name.size() + 1);
    at = end + 1;
  }
  return {};
}

std::string percentEncoded(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      out += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

// A session id in a path: digits only, in range (a page's address is typed by people).
std::optional<std::int64_t> sessionId(const std::string& text) {
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  const std::int64_t id = std::stoll(text);
  return id > 0 ? std::optional<std::int64_t>(id) : std::nullopt;
}

std::string contentTypeOf(std::string_view path) {
  const auto ends = [&](std::string_view suffix) {
    return path.size() >= suffix.size() && path.substr(path.size() - suffix.size()) == suffix;
  };
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".txt")) return "text/plain; charset=utf-8";
  return "application/octet-stream";
}

std::optional<HttpResponse> asset(std::string_view path) {
  for (const EmbeddedFile& f : embeddedFiles())
    if (f.path == path) {
      HttpResponse r;
      r.contentType = contentTypeOf(path);
      r.body.assign(f.data, f.size);
      return r;
    }
  return std::nullopt;
}

// A request that changes something must come from our own pages: JSON (no HTML form can send
// it), from this origin when the browser says where it comes from.
std::optional<HttpResponse> refusedAsCrossSite(const HttpRequest& request) {
  const std::string type = request.header("content-type");
  if (type.rfind("application/json", 0) != 0)
    return problem(415, "a change is sent as JSON (Content-Type: application/json)",
                   "send the body as JSON, as the review's pages do");
  if (request.header("sec-fetch-site") == "cross-site")
    return problem(403, "a request from another site is refused", "use the review's own pages");
  const std::string origin = request.header("origin");
  const std::string host = request.header("host");
  if (!origin.empty() && origin != "http://" + host && origin != "https://" + host)
    return problem(403, "a request from another site is refused", "use the review's own pages");
  return std::nullopt;
}

// The request's JSON body as an object, or why not.
std::variant<json, HttpResponse> bodyObject(const HttpRequest& request) {
  json body = json::parse(request.body, nullptr, false);
  if (body.is_discarded() || !body.is_object())
    return problem(400, "the request's body is not a JSON object", "send a JSON object, e.g. {\"why\": \"…\"}");
  return body;
}

// A store's or a capture's refusal, in the API's words and status.
HttpResponse refusal(const std::exception& e) {
  if (const auto* s = dynamic_cast<const db::StoreError*>(&e)) {
    switch (s->kind()) {
      case db::StoreErrorKind::Refused:
        return problem(403, s->what(), s->remedy().empty() ? "ask a curator" : s->remedy());
      case db::StoreErrorKind::Conflict: return problem(409, s->what(), s->remedy());
      case db::StoreErrorKind::Input: return problem(400, s->what(), s->remedy());
      case db::StoreErrorKind::Unreachable:
      case db::StoreErrorKind::Interrupted:
        return problem(503, "the lab server cannot be reached", "try again; log in again if it persists");
      default: return problem(500, s->what(), s->remedy());
    }
  }
  if (dynamic_cast<const std::invalid_argument*>(&e) != nullptr)
    return problem(409, e.what(), "reload the session: its state does not take this decision");
  if (dynamic_cast<const model::InputError*>(&e) != nullptr)
    return problem(409, e.what(), "the session does not make this file yet: its capture is not whole");
  if (dynamic_cast<const acq::SessionError*>(&e) != nullptr)
    return problem(409, e.what(), "the session's events do not replay: verify it (leafdig sessions verify)");
  return problem(500, e.what(), "see the web server's log");
}

}  // namespace

std::string loginUrl(const std::string& serverUrl, const std::string& login, const std::string& password) {
  std::size_t scheme = std::string::npos;
  for (const char* s : {"postgresql://", "postgres://"})
    if (serverUrl.rfind(s, 0) == 0) scheme = std::string(s).size();
  if (scheme == std::string::npos)
    throw std::invalid_argument("the lab server is given as postgresql://HOST[:PORT]/DATABASE");
  std::size_t end = serverUrl.find_first_of("/?", scheme);
  if (end == std::string::npos) end = serverUrl.size();
  std::string host = serverUrl.substr(scheme, end - scheme);
  if (const std::size_t at = host.rfind('@'); at != std::string::npos) host = host.substr(at + 1);
  std::string rest = serverUrl.substr(end);
  // The web server's own ~/.pgpass never stands in for a browser's password.
  rest += (rest.find('?') == std::string::npos ? "?" : "&") + std::string("passfile=/dev/null");
  if (rest.front() == '?') rest = "/" + rest;
  return serverUrl.substr(0, scheme) + percentEncoded(login) + ":" + percentEncoded(password) + "@" + host + rest;
}

WebApp::WebApp(WebOptions options) : options_(std::move(options)) {
  (void)loginUrl(options_.serverUrl, "x", "x");  // refuses a URL that is not postgresql:// now, not at a login
}

WebApp::~WebApp() = default;

HttpResponse WebApp::handle(const HttpRequest& request) {
  HttpResponse r;
  try {
    r = route(request);
  } catch (const std::exception& e) {
    r = refusal(e);
  }
  for (const auto& [name, value] : kSecurityHeaders) r.headers.emplace_back(name, value);
  return r;
}

HttpResponse WebApp::route(const HttpRequest& request) {
  const std::string& path = request.path;
  if (path.rfind("/api/", 0) != 0) {
    if (request.method != "GET" && request.method != "HEAD")
      return problem(405, "pages are read with GET", "use the API under /api/ to change anything");
    if (path.rfind("/static/", 0) == 0)
      if (auto a = asset(std::string_view(path).substr(8)); a && a->contentType.rfind("text/html", 0) != 0) return *a;
    // The pages are one document; its script reads the address (/, /sessions/12, /login).
    if (path == "/" || path == "/login" || (path.rfind("/sessions/", 0) == 0 && sessionId(path.substr(10))))
      return *asset("index.html");
    return problem(404, "no page at " + path, "start from /");
  }
  if (path == "/api/login") {
    if (request.method != "POST") return problem(405, "log in with POST", "POST {\"login\", \"password\"} as JSON");
    return login(request);
  }
  Call call;
  call.session = sessionOf(request);
  if (!call.session) return problem(401, "not logged in (or the session ended)", "log in again");
  if (request.method == "POST") {
    if (auto refused = refusedAsCrossSite(request)) return *refused;
    if (!sameSecret(request.header("x-csrf-token"), call.session->csrf))
      return problem(403, "the request lacks this session's CSRF token",
                     "send the token GET /api/me gives as the X-CSRF-Token header");
    if (path == "/api/logout") return logout(request);
  }
  return api(request, call);
}

std::shared_ptr<WebApp::Session> WebApp::sessionOf(const HttpRequest& request) {
  const std::string token = cookieValue(request.header("cookie"), kCookie);
  if (token.empty()) return nullptr;
  const std::lock_guard lock(mutex_);
  const auto it = sessions_.find(token);
  if (it == sessions_.end()) return nullptr;
  const auto now = Clock::now();
  if (now - it->second->lastUsed > options_.idle || now - it->second->created > options_.longest) {
    sessions_.erase(it);  // its connection closes with the last request using it
    return nullptr;
  }
  it->second->lastUsed = now;
  return it->second;
}

bool WebApp::throttled(const std::string& login, const std::string& address) {
  const std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  // Old failures are forgotten, and with them keys that hold none.
  for (auto it = failures_.begin(); it != failures_.end();) {
    auto& times = it->second;
    times.erase(std::remove_if(times.begin(), times.end(),
                               [&](Clock::time_point t) { return now - t > options_.failedLoginWindow; }),
                times.end());
    it = times.empty() ? failures_.erase(it) : std::next(it);
  }
  for (const std::string& key : {"login " + login, "address " + address})
    if (const auto it = failures_.find(key);
        it != failures_.end() && static_cast<int>(it->second.size()) >= options_.failedLoginsAllowed)
      return true;
  return false;
}

void WebApp::failedLogin(const std::string& login, const std::string& address) {
  const std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  failures_["login " + login].push_back(now);
  failures_["address " + address].push_back(now);
}

HttpResponse WebApp::login(const HttpRequest& request) {
  const auto started = Clock::now();
  if (auto refused = refusedAsCrossSite(request)) return *refused;
  auto parsed = bodyObject(request);
  if (auto* bad = std::get_if<HttpResponse>(&parsed)) return *bad;
  const json& body = std::get<json>(parsed);
  const auto who = textField(body, "login");
  const auto password = textField(body, "password");
  if (!who || !password || who->empty() || password->empty() || who->size() > kLongestLogin ||
      password->size() > kLongestPassword)
    return problem(400, "a login needs a login name and its password (text)",
                   "send {\"login\": \"NAME\", \"password\": \"…\"}");
  const auto refuse = [&](int status, const std::string& error, const std::string& whatToDo) {
    std::this_thread::sleep_until(started + options_.refusedLoginTime);
    return problem(status, error, whatToDo);
  };
  if (throttled(*who, request.remoteAddress))
    return refuse(429, "too many refused logins for this login or from this address",
                  "wait " + std::to_string(options_.failedLoginWindow.count() / 60) + " minutes, then try again");
  std::unique_ptr<db::LabStore> store;
  try {
    store = std::make_unique<db::LabStore>(loginUrl(options_.serverUrl, *who, *password));
  } catch (const db::StoreError& e) {
    const std::string words = e.what();
    // The server says the same of an unknown login and a wrong password; so do we, in the same time.
    if (words.find("authentication failed") != std::string::npos || words.find("password") != std::string::npos ||
        words.find("does not exist") != std::string::npos || words.find("no pg_hba.conf entry") != std::string::npos) {
      failedLogin(*who, request.remoteAddress);
      return refuse(401, "the login or the password is not right", "check both and try again");
    }
    return refuse(503, "the lab server cannot be reached",
                  "try again later; if it persists, tell the lab's administrator");
  }
  if (!store->passwordChecked())
    return refuse(403, "the lab server let this login in without checking its password",
                  "the lab's administrator requires passwords (scram-sha-256) in pg_hba.conf for the web server's "
                  "address (docs/web.md)");
  const auto role = store->role();
  if (!role)
    return refuse(403, "this login is in none of leafdig's groups",
                  "ask the lab's administrator (leafdig server add-user)");
  auto session = std::make_shared<Session>();
  session->login = *store->login();
  session->role = *role;
  session->csrf = randomToken();
  session->store = std::move(store);
  session->created = session->lastUsed = Clock::now();
  const std::string token = randomToken();
  {
    const std::lock_guard lock(mutex_);
    // A login's sessions beyond the limit end, oldest first (each holds a connection).
    std::vector<std::map<std::string, std::shared_ptr<Session>>::iterator> mine;
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
      if (it->second->login == session->login) mine.push_back(it);
    std::sort(mine.begin(), mine.end(),
              [](const auto& a, const auto& b) { return a->second->created < b->second->created; });
    for (std::size_t i = 0; i + static_cast<std::size_t>(options_.sessionsPerLogin) <= mine.size(); ++i)
      sessions_.erase(mine[i]);
    sessions_[token] = session;
  }
  HttpResponse r =
      jsonAnswer(200, json{{"login", session->login}, {"role", db::toString(session->role)}, {"csrf", session->csrf}});
  r.headers.emplace_back("Set-Cookie",
                         std::string(kCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict; Max-Age=" +
                             std::to_string(options_.longest.count()) + (options_.secureCookie ? "; Secure" : ""));
  return r;
}

HttpResponse WebApp::logout(const HttpRequest& request) {
  const std::string token = cookieValue(request.header("cookie"), kCookie);
  {
    const std::lock_guard lock(mutex_);
    sessions_.erase(token);
  }
  HttpResponse r = jsonAnswer(200, json{{"logged_out", true}});
  r.headers.emplace_back("Set-Cookie", std::string(kCookie) + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0" +
                                           (options_.secureCookie ? "; Secure" : ""));
  return r;
}

HttpResponse WebApp::api(const HttpRequest& request, Call& call) {
  Session& s = *call.session;
  const std::string& path = request.path;
  const std::lock_guard use(s.use);
  if (path == "/api/me" && request.method == "GET")
    return jsonAnswer(200, json{{"login", s.login}, {"role", db::toString(s.role)}, {"csrf", s.csrf}});
  // The list's choices from the tables the CLI's --status and --kind take (no page retypes them).
  if (path == "/api/choices" && request.method == "GET") {
    json statuses = json::array();
    for (const char* status : db::kSessionStatuses) statuses.push_back(status);
    return jsonAnswer(200, json{{"statuses", statuses},
                                {"kinds", {std::string(acq::kLeafCapture.word), std::string(acq::kPlantCapture.word)}},
                                {"decisions", {"approve", "reject", "reopen"}}});
  }
  if (path == "/api/sessions" && request.method == "GET") {
    SessionsOptions filter;
    const auto param = [&](const char* key) {
      const auto it = request.query.find(key);
      return it == request.query.end() ? std::string() : it->second;
    };
    filter.status = param("status");
    filter.kind = param("kind");
    filter.plant = param("plant");
    filter.station = param("station");
    filter.since = param("since");
    std::vector<db::SessionInfo> shown;
    for (auto& info : s.store->sessions())
      if (listed(info, filter)) shown.push_back(std::move(info));
    return jsonAnswer(200, sessionListJson(*s.store, shown));
  }
  const std::string prefix = "/api/sessions/";
  if (path.rfind(prefix, 0) != 0) return problem(404, "no API at " + path, "see docs/web.md for the API");
  const std::string rest = path.substr(prefix.size());
  const std::size_t slash = rest.find('/');
  const auto id = sessionId(rest.substr(0, slash));
  const std::string action = slash == std::string::npos ? std::string() : rest.substr(slash + 1);
  if (!id)
    return problem(404, "no session " + rest.substr(0, slash), "give a session's number, as /api/sessions lists it");
  // A session the login may not see is as absent as one that does not exist.
  if (!s.store->session(*id))
    return problem(404, "no session " + std::to_string(*id) + " that this login may see",
                   "pick one from /api/sessions");
  if (action.empty() && request.method == "GET") return jsonAnswer(200, sessionJson(*s.store, *id));
  if (action == "export" && request.method == "GET") return exportFile(*s.store, *id, request);
  if (action == "review" && request.method == "GET") return leafReview(*s.store, *id);
  if (action == "surveys" && request.method == "GET") return plantSurveys(*s.store, *id);
  if (request.method == "POST" && action == "correct") {
    auto parsed = bodyObject(request);
    if (auto* bad = std::get_if<HttpResponse>(&parsed)) return *bad;
    return correction(*s.store, *id, std::get<json>(parsed));
  }
  if (request.method == "POST" && (action == "approve" || action == "reject" || action == "reopen")) {
    auto parsed = bodyObject(request);
    if (auto* bad = std::get_if<HttpResponse>(&parsed)) return *bad;
    const auto why = textField(std::get<json>(parsed), "why");
    if (!why || why->find_first_not_of(" \t\r\n") == std::string::npos || why->size() > kLongestReason)
      return problem(400, "a decision needs a reason (why)", "send {\"why\": \"…\"} (at most 4000 characters)");
    const std::string who = s.store->signature("");
    if (action == "reopen")
      (void)acq::reopen(*s.store, *id, who, *why);
    else
      (void)acq::review(*s.store, *id, action == "approve" ? "approved" : "rejected", who, *why);
    return jsonAnswer(200, sessionJson(*s.store, *id));
  }
  return problem(404, "no API at " + path + " for " + request.method, "see docs/web.md for the API");
}

}  // namespace leafdig::cli::web
