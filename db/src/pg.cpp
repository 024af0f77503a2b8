#include "pg.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <map>

#include "leafdig/db/server_url.hpp"

namespace leafdig::db::pg {

std::int64_t Result::int64(int row, int col) const {
  const std::string t = text(row, col);
  std::int64_t v = 0;
  std::from_chars(t.data(), t.data() + t.size(), v);
  return v;
}

double Result::number(int row, int col) const {
  return std::strtod(text(row, col).c_str(), nullptr);
}

bool isSecretOption(const std::string& key) {
  return key == "password" || key == "sslpassword";
}

// libpq's own reading of a URL or key=value string (the same parser the connection uses),
// or nothing when libpq cannot read it. libpq's error text is dropped: it may quote the
// password.
std::optional<ConnectionOptions> parseConnection(const std::string& text) {
  char* error = nullptr;
  PQconninfoOption* options = PQconninfoParse(text.c_str(), &error);
  if (error) PQfreemem(error);
  if (!options) return std::nullopt;
  ConnectionOptions out;
  for (const PQconninfoOption* o = options; o->keyword; ++o)
    if (o->val) out.emplace_back(o->keyword, o->val);
  PQconninfoFree(options);
  return out;
}

std::vector<std::string> connectionSecrets(const std::string& url) {
  std::vector<std::string> out;
  if (const auto parsed = parseConnection(url))
    for (const auto& [key, value] : *parsed)
      if (isSecretOption(key) && !value.empty()) out.push_back(value);
  // As typed, too: user:PASSWORD@ before libpq decodes it (or when it cannot).
  if (isServerUrl(url)) {
    const std::size_t start = url.find("://") + 3;
    const std::size_t slash = url.find('/', start);
    const std::size_t at = url.rfind('@', slash == std::string::npos ? std::string::npos : slash);
    if (at != std::string::npos && at > start) {
      const std::size_t colon = url.find(':', start);
      if (colon != std::string::npos && colon < at && at > colon + 1)
        out.push_back(url.substr(colon + 1, at - colon - 1));
    }
  }
  std::sort(out.begin(), out.end(), [](const std::string& a, const std::string& b) { return a.size() > b.size(); });
  return out;
}

std::string withoutSecrets(std::string text, const std::vector<std::string>& secrets) {
  for (const std::string& secret : secrets)
    for (std::size_t p = text.find(secret); p != std::string::npos; p = text.find(secret, p + 3))
      text.replace(p, secret.size(), "***");
  return text;
}

namespace {

std::string field(const PGresult* r, int code) {
  const char* f = PQresultErrorField(r, code);
  return f ? f : "";
}

}  // namespace

Connection::Connection(const std::string& url) : where_(redactUrl(url)), secrets_(connectionSecrets(url)) {
  // A URL libpq cannot read is refused before anything is sent, without libpq's words
  // (which quote the part it could not read, password and all).
  if (!parseConnection(url))
    throw Error(StoreErrorKind::Input, "the lab server's address " + where_ + " cannot be read by libpq",
                "write it as postgresql://USER@HOST[:PORT]/DATABASE[?sslmode=…]: every % followed by two hex digits, "
                "only libpq's parameter names (sslmode, sslrootcert, connect_timeout, …); keep the password in "
                "~/.pgpass (docs/lab.md). It is not repeated here because it may hold a password",
                "08P01");
  // libpq takes a URL or key=value pairs; a connect timeout unless the caller set one, and
  // our name in the server's activity view.
  const char* keys[] = {"dbname", "connect_timeout", "application_name", nullptr};
  const char* values[] = {url.c_str(), "10", "leafdig", nullptr};
  conn_ = PQconnectdbParams(keys, values, 1);  // expand_dbname: the URL's own settings win
  if (conn_ == nullptr || PQstatus(conn_) != CONNECTION_OK) {
    std::string why = conn_ ? PQerrorMessage(conn_) : "out of memory";
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    if (conn_) PQfinish(conn_);
    conn_ = nullptr;
    throw Error(StoreErrorKind::Unreachable,
                "cannot connect to the lab server " + where_ + ": " + withoutSecrets(why, secrets_),
                "check the URL (host, port, database, user), the network and the password (~/.pgpass or "
                "PGPASSFILE; docs/lab.md); nothing was changed",
                "08001");
  }
  // Every timestamp the server shows in UTC, and text in UTF-8 whatever the server's locale.
  (void)exec("SET TIME ZONE 'UTC'");
  if (PQsetClientEncoding(conn_, "UTF8") != 0)
    throw Error(StoreErrorKind::Input, "the lab server " + where_ + " cannot talk UTF-8",
                "create the database with ENCODING 'UTF8'", "22021");
}

Connection::~Connection() {
  if (conn_) PQfinish(conn_);
}

Result Connection::exec(const std::string& sql, const std::vector<Param>& params) {
  std::vector<const char*> values;
  values.reserve(params.size());
  for (const auto& p : params) values.push_back(p ? p->c_str() : nullptr);
  return check(
      PQexecParams(conn_, sql.c_str(), static_cast<int>(values.size()), nullptr, values.data(), nullptr, nullptr, 0));
}

void Connection::execScript(const std::string& sql) {
  (void)check(PQexec(conn_, sql.c_str()));
}

Result Connection::check(PGresult* r) {
  const ExecStatusType status = r ? PQresultStatus(r) : PGRES_FATAL_ERROR;
  if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return Result(r);
  // The server's own words: its primary message, detail and hint, and the SQLSTATE.
  std::string state = r ? field(r, PG_DIAG_SQLSTATE) : "";
  std::string message = r ? field(r, PG_DIAG_MESSAGE_PRIMARY) : "";
  const std::string detail = r ? field(r, PG_DIAG_MESSAGE_DETAIL) : "";
  std::string hint = r ? field(r, PG_DIAG_MESSAGE_HINT) : "";
  if (r) PQclear(r);
  if (message.empty()) {
    message = PQerrorMessage(conn_);
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  }
  if (!detail.empty()) message += " (" + detail + ")";
  const bool lost = PQstatus(conn_) == CONNECTION_BAD || state.rfind("08", 0) == 0 || state.empty();
  StoreErrorKind kind = StoreErrorKind::Input;
  if (lost) {
    kind = StoreErrorKind::Unreachable;
    if (state.empty()) state = "08006";
    if (hint.empty())
      hint =
          "the connection to the lab server was lost; what was not committed was rolled back on the server: "
          "run the command again, it continues where the server stands";
  } else if (state == "42501") {
    kind = StoreErrorKind::Refused;
  } else if (state.rfind("LD", 0) == 0 || state == "23505" || state == "40001") {
    kind = StoreErrorKind::Conflict;
  }
  if (hint.empty()) hint = "the lab server refused it; nothing of this statement was kept";
  throw Error(kind, "lab server " + where_ + ": " + withoutSecrets(message, secrets_), withoutSecrets(hint, secrets_),
              state);
}

void Connection::rollback() noexcept {
  if (conn_ && PQtransactionStatus(conn_) != PQTRANS_IDLE) PQclear(PQexec(conn_, "ROLLBACK"));
}

std::string Connection::quoteIdentifier(const std::string& name) const {
  char* q = PQescapeIdentifier(conn_, name.c_str(), name.size());
  if (!q)
    throw Error(StoreErrorKind::Input, "cannot quote the name '" + name + "'", "use a shorter plain name", "22000");
  std::string out(q);
  PQfreemem(q);
  return out;
}

std::string Connection::quoteLiteral(const std::string& value) const {
  char* q = PQescapeLiteral(conn_, value.c_str(), value.size());
  if (!q) throw Error(StoreErrorKind::Input, "cannot quote a value", "check the text is UTF-8", "22000");
  std::string out(q);
  PQfreemem(q);
  return out;
}

std::string Connection::encryptPassword(const std::string& password, const std::string& login) const {
  char* v = PQencryptPasswordConn(conn_, password.c_str(), login.c_str(), "scram-sha-256");
  if (!v)
    throw Error(StoreErrorKind::Input, std::string("cannot encrypt the password: ") + PQerrorMessage(conn_),
                "check the password file holds one line of text", "22000");
  std::string out(v);
  PQfreemem(v);
  return out;
}

bool hasGenesisForms(Connection& c) {
  return c.exec(
              "SELECT 1 FROM information_schema.columns WHERE table_schema = 'leafdig' AND table_name = 'sessions' "
              "AND column_name = 'genesis_form'")
             .rows() > 0;
}

}  // namespace leafdig::db::pg

namespace leafdig::db {

bool isServerUrl(const std::string& text) {
  return text.rfind("postgresql://", 0) == 0 || text.rfind("postgres://", 0) == 0;
}

namespace {

std::string percentEncoded(const std::string& text) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) != 0 || c == '-' || c == '.' || c == '_' || c == '~' || c == ',' || c == '/') {
      out += ch;
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

}  // namespace

namespace {

// The URL as libpq reads it, each secret (password, sslpassword) replaced by `secret`, or left
// out when `secret` is null.
std::string renderUrl(const std::string& url, const char* secret) {
  const bool asUrl = isServerUrl(url);
  if (!asUrl && url.find('=') == std::string::npos) return url;  // a file's path
  const auto parsed = pg::parseConnection(url);
  if (!parsed) {
    if (asUrl)
      return url.substr(0, url.find("://") + 3) + "(a URL libpq cannot read; not shown: it may hold a password)";
    std::string lower = url;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return lower.find("password") == std::string::npos
               ? url  // a file's path with '=' in its name
               : "(a connection string libpq cannot read; not shown: it may hold a password)";
  }
  std::map<std::string, std::string> o(parsed->begin(), parsed->end());
  const auto take = [&](const char* key) {
    const auto at = o.find(key);
    if (at == o.end()) return std::optional<std::string>();
    std::string v = at->second;
    o.erase(at);
    return std::optional<std::string>(v);
  };
  if (!asUrl) {
    std::string out;
    for (const auto& [key, value] : *parsed) {
      if (pg::isSecretOption(key) && !secret) continue;
      out += (out.empty() ? "" : " ") + key + "=" + (pg::isSecretOption(key) ? std::string(secret) : value);
    }
    return out;
  }
  const auto user = take("user");
  const bool password = take("password").has_value() && secret;
  const auto host = take("host");
  const auto port = take("port");
  const auto dbname = take("dbname");
  std::string out = url.substr(0, url.find("://") + 3);
  if (user || password) out += percentEncoded(user.value_or("")) + (password ? std::string(":") + secret : "") + "@";
  if (host) out += host->find(':') != std::string::npos ? "[" + *host + "]" : percentEncoded(*host);
  if (port) out += ":" + percentEncoded(*port);
  if (dbname) out += "/" + percentEncoded(*dbname);
  std::string query;
  for (const auto& [key, value] : o) {
    if (pg::isSecretOption(key) && !secret) continue;
    query += (query.empty() ? "?" : "&") + key + "=" +
             (pg::isSecretOption(key) ? std::string(secret) : percentEncoded(value));
  }
  return out + query;
}

}  // namespace

std::string redactUrl(const std::string& url) {
  return renderUrl(url, "***");
}

std::optional<std::string> urlWithoutSecrets(const std::string& url) {
  const bool asUrl = isServerUrl(url);
  if (!asUrl && url.find('=') == std::string::npos) return url;
  if (!pg::parseConnection(url)) return std::nullopt;
  return renderUrl(url, nullptr);
}

}  // namespace leafdig::db
