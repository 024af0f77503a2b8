// A throw-away PostgreSQL server for the lab tests and benchmarks: a new cluster (initdb)
// in a temporary directory, started with pg_ctl on a free local port, stopped and removed
// at the end. No mock: Debian's postgresql-15 binaries (pg_config --bindir). PostgreSQL
// refuses to run as root, so when the tests run as root (CI does) the cluster runs as the
// `postgres` user (runuser). Passwords are SCRAM over TCP on 127.0.0.1, as in a lab.
//
// Also a minimal libpq client of its own (`Sql`), so the tests read and write the server
// without leafdig's code.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <libpq-fe.h>
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace leafdig::test {

inline int runCommand(const std::vector<std::string>& argv, const std::string& logFile) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(logFile.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0666);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

inline int freeLocalPort() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t n = sizeof a;
  ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &n);
  ::close(s);
  return ntohs(a.sin_port);
}

// Statements against the server through libpq directly; failures come back as text.
class Sql {
 public:
  explicit Sql(const std::string& url) : c_(PQconnectdb(url.c_str())) {
    if (PQstatus(c_) != CONNECTION_OK) {
      const std::string why = std::string("test connection: ") + PQerrorMessage(c_);
      PQfinish(c_);  // a refused connection is still libpq's to free
      throw std::runtime_error(why);
    }
  }
  Sql(const Sql&) = delete;
  Sql& operator=(const Sql&) = delete;
  ~Sql() { PQfinish(c_); }
  // The rows as text (NULL as "\N"); throws std::runtime_error with the server's message.
  std::vector<std::vector<std::string>> rows(const std::string& sql, const std::vector<std::string>& params = {}) {
    std::vector<const char*> v;
    for (const auto& p : params) v.push_back(p.c_str());
    PGresult* r = PQexecParams(c_, sql.c_str(), static_cast<int>(v.size()), nullptr, v.data(), nullptr, nullptr, 0);
    const auto st = PQresultStatus(r);
    if (st != PGRES_TUPLES_OK && st != PGRES_COMMAND_OK) {
      const std::string why = PQresultErrorMessage(r);
      PQclear(r);
      throw std::runtime_error(why);
    }
    std::vector<std::vector<std::string>> out;
    for (int i = 0; i < PQntuples(r); ++i) {
      std::vector<std::string> row;
      for (int j = 0; j < PQnfields(r); ++j)
        row.push_back(PQgetisnull(r, i, j)
                          ? "\\N"
                          : std::string(PQgetvalue(r, i, j), static_cast<std::size_t>(PQgetlength(r, i, j))));
      out.push_back(std::move(row));
    }
    PQclear(r);
    return out;
  }
  std::string value(const std::string& sql, const std::vector<std::string>& params = {}) {
    const auto r = rows(sql, params);
    return r.empty() || r[0].empty() ? "" : r[0][0];
  }
  // Several statements without parameters (a migration's text); throws with the server's message.
  void script(const std::string& sql) {
    PGresult* r = PQexec(c_, sql.c_str());
    const auto st = PQresultStatus(r);
    const std::string why = PQresultErrorMessage(r);
    PQclear(r);
    if (st != PGRES_TUPLES_OK && st != PGRES_COMMAND_OK) throw std::runtime_error(why);
  }
  // The error text of a statement expected to fail ("" if it succeeded).
  std::string error(const std::string& sql, const std::vector<std::string>& params = {}) {
    try {
      (void)rows(sql, params);
      return "";
    } catch (const std::runtime_error& e) {
      return e.what();
    }
  }

 private:
  PGconn* c_;
};

class PgCluster {
 public:
  static constexpr const char* kAdmin = "leafdig_admin";

  // tls: the server also speaks TLS with a self-signed certificate for localhost and
  // 127.0.0.1 (certificateFile() is its own root, for sslmode=verify-full).
  explicit PgCluster(bool tls = false) {
    bin_ = bindir();
    char tmpl[] = "/tmp/leafdig-pg-XXXXXX";
    if (::mkdtemp(tmpl) == nullptr) throw std::runtime_error("mkdtemp failed");
    dir_ = tmpl;
    password_ = "adm'in pass " + std::to_string(::getpid());
    std::ofstream(dir_ / "pw") << password_ << "\n";
    log_ = (dir_ / "server.log").string();
    if (::geteuid() == 0) {
      const passwd* pw = ::getpwnam("postgres");
      if (pw == nullptr) throw std::runtime_error("running as root and there is no 'postgres' user to run PostgreSQL");
      for (const auto& p : {dir_, dir_ / "pw"}) {
        if (::chown(p.c_str(), pw->pw_uid, pw->pw_gid) != 0) throw std::runtime_error("chown " + p.string());
      }
      asUser_ = {"runuser", "-u", "postgres", "--"};
      std::ofstream(log_).close();
      (void)::chown(log_.c_str(), pw->pw_uid, pw->pw_gid);
    }
    if (run({bin_ + "/initdb", "-D", (dir_ / "data").string(), "-U", kAdmin, "--pwfile", (dir_ / "pw").string(),
             "--auth-local=trust", "--auth-host=scram-sha-256", "-E", "UTF8", "--locale=C", "--no-sync"}) != 0)
      throw std::runtime_error("initdb failed: " + logText());
    std::string tlsOptions;
    if (tls) {
      const std::string key = (dir_ / "server.key").string();
      if (runCommand({"openssl", "req", "-new", "-x509", "-days", "2", "-nodes", "-subj", "/CN=localhost", "-addext",
                      "subjectAltName=DNS:localhost,IP:127.0.0.1", "-keyout", key, "-out", certificateFile()},
                     log_) != 0)
        throw std::runtime_error("openssl could not make a certificate: " + logText());
      if (::geteuid() == 0) {
        const passwd* pw = ::getpwnam("postgres");
        for (const auto& f : {key, certificateFile()}) (void)::chown(f.c_str(), pw->pw_uid, pw->pw_gid);
      }
      std::filesystem::permissions(key, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
      tlsOptions = " -c ssl=on -c ssl_cert_file=" + certificateFile() + " -c ssl_key_file=" + key;
    }
    for (int attempt = 0; attempt < 5; ++attempt) {
      port_ = freeLocalPort();
      const std::string options = "-p " + std::to_string(port_) + " -k " + dir_.string() +
                                  " -c listen_addresses=127.0.0.1 -c fsync=off -c max_connections=60" + tlsOptions;
      if (run({bin_ + "/pg_ctl", "-D", (dir_ / "data").string(), "-l", log_, "-w", "-t", "60", "-o", options,
               "start"}) == 0) {
        started_ = true;
        break;
      }
    }
    if (!started_) throw std::runtime_error("pg_ctl start failed: " + logText());
  }
  PgCluster(const PgCluster&) = delete;
  PgCluster& operator=(const PgCluster&) = delete;
  ~PgCluster() {
    if (started_) (void)run({bin_ + "/pg_ctl", "-D", (dir_ / "data").string(), "-m", "immediate", "-w", "stop"});
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  [[nodiscard]] int port() const { return port_; }
  [[nodiscard]] std::string certificateFile() const { return (dir_ / "server.crt").string(); }
  [[nodiscard]] const std::string& adminPassword() const { return password_; }
  // postgresql://login:password@127.0.0.1:port/db (the password percent-encoded).
  [[nodiscard]] std::string url(const std::string& login, const std::string& password, const std::string& db,
                                std::optional<int> port = {}) const {
    return "postgresql://" + encode(login) + ":" + encode(password) +
           "@127.0.0.1:" + std::to_string(port.value_or(port_)) + "/" + db;
  }
  [[nodiscard]] std::string adminUrl(const std::string& db = "postgres") const { return url(kAdmin, password_, db); }
  // A new, empty UTF-8 database.
  std::string createDatabase() {
    const std::string name = "lab" + std::to_string(++databases_);
    Sql(adminUrl()).rows("CREATE DATABASE " + name + " ENCODING 'UTF8' TEMPLATE template0");
    return name;
  }
  [[nodiscard]] std::string logText() const {
    std::ifstream in(log_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  static std::string encode(const std::string& s) {
    std::string out;
    for (const unsigned char c : s) {
      if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
        out += static_cast<char>(c);
      } else {
        char b[4];
        std::snprintf(b, sizeof b, "%%%02X", c);
        out += b;
      }
    }
    return out;
  }

 private:
  static std::string bindir() {
    std::string dir;
    if (FILE* p = ::popen("pg_config --bindir 2>/dev/null", "r")) {
      char buf[512];
      if (std::fgets(buf, sizeof buf, p)) dir = buf;
      ::pclose(p);
    }
    while (!dir.empty() && (dir.back() == '\n' || dir.back() == ' ')) dir.pop_back();
    if (!dir.empty() && std::filesystem::exists(dir + "/initdb")) return dir;
    for (const char* v : {"17", "16", "15"}) {
      const std::string d = std::string("/usr/lib/postgresql/") + v + "/bin";
      if (std::filesystem::exists(d + "/initdb")) return d;
    }
    throw std::runtime_error("no PostgreSQL server binaries (initdb): install Debian's postgresql");
  }
  int run(std::vector<std::string> argv) const {
    argv.insert(argv.begin(), asUser_.begin(), asUser_.end());
    return runCommand(argv, log_);
  }

  std::string bin_;
  std::filesystem::path dir_;
  std::string password_, log_;
  std::vector<std::string> asUser_;
  int port_ = 0;
  bool started_ = false;
  int databases_ = 0;
};

}  // namespace leafdig::test
