// A thin RAII layer over libpq (the PostgreSQL client library, Debian libpq-dev) for the lab
// server: one connection, statements with parameters only (never text pasted into SQL),
// results as strings, failures as StoreError with the server's own words. Private to db/.
//
// libpqxx was the other candidate; Debian 12 ships 6.4, which predates C++20, and we need
// only parameterised statements, transactions and libpq's escaping of identifiers for the
// few DDL statements that take no parameters: this file is that much.
//
// Thread contract: one thread at a time per connection.
#pragma once

#include <libpq-fe.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"

namespace leafdig::db::pg {

// A failure the server reported, with its SQLSTATE (23505: the row is there already, …).
class Error : public StoreError {
 public:
  Error(StoreErrorKind kind, const std::string& what, std::string remedy, std::string state)
      : StoreError(kind, what, std::move(remedy)), state_(std::move(state)) {}
  [[nodiscard]] const std::string& sqlState() const noexcept { return state_; }

 private:
  std::string state_;
};

// libpq's own reading of a URL or key=value string (the parser the connection uses): every
// option it sets, in libpq's order; nothing when libpq cannot read it (libpq's words are
// dropped: they may quote the password).
using ConnectionOptions = std::vector<std::pair<std::string, std::string>>;
std::optional<ConnectionOptions> parseConnection(const std::string& text);
// password and sslpassword: never printed.
bool isSecretOption(const std::string& key);
// The secrets a URL carries (libpq's reading, and the user:PASSWORD@ part as typed), longest
// first; and a text with each of them replaced by ***.
std::vector<std::string> connectionSecrets(const std::string& url);
std::string withoutSecrets(std::string text, const std::vector<std::string>& secrets);

// A parameter: text, or SQL NULL.
using Param = std::optional<std::string>;

class Result {
 public:
  explicit Result(PGresult* r) : r_(r, &PQclear) {}
  [[nodiscard]] int rows() const { return PQntuples(r_.get()); }
  [[nodiscard]] bool isNull(int row, int col) const { return PQgetisnull(r_.get(), row, col) != 0; }
  [[nodiscard]] std::string text(int row, int col) const {
    return std::string(PQgetvalue(r_.get(), row, col), static_cast<std::size_t>(PQgetlength(r_.get(), row, col)));
  }
  [[nodiscard]] std::int64_t int64(int row, int col) const;
  [[nodiscard]] double number(int row, int col) const;

 private:
  std::unique_ptr<PGresult, void (*)(PGresult*)> r_;
};

class Connection {
 public:
  // Connects (libpq URL or key=value string; `connect_timeout` 10 s unless the URL says).
  // Throws StoreError(Unreachable) with the server's words and the URL without password.
  explicit Connection(const std::string& url);
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  // Runs one statement with $1, $2, … parameters. Throws StoreError: Refused for a
  // permission or policy refusal, Conflict for a chain the server refused, Unreachable for
  // a lost connection, Input otherwise; the message is the server's, the remedy its hint.
  Result exec(const std::string& sql, const std::vector<Param>& params = {});
  // Several statements without parameters (the schema's migrations): our own text only.
  void execScript(const std::string& sql);
  void begin() { (void)exec("BEGIN"); }
  void commit() { (void)exec("COMMIT"); }
  void rollback() noexcept;

  [[nodiscard]] std::string quoteIdentifier(const std::string& name) const;
  [[nodiscard]] std::string quoteLiteral(const std::string& value) const;
  // A SCRAM-SHA-256 verifier of the password, computed here: the password itself never
  // travels to the server or into its logs.
  [[nodiscard]] std::string encryptPassword(const std::string& password, const std::string& login) const;
  [[nodiscard]] const std::string& where() const { return where_; }  // the redacted URL
  [[nodiscard]] std::string user() const { return PQuser(conn_); }
  // Whether the server asked for the password (a `trust` line in pg_hba.conf does not).
  [[nodiscard]] bool usedPassword() const { return PQconnectionUsedPassword(conn_) == 1; }

 private:
  Result check(PGresult* r);

  PGconn* conn_ = nullptr;
  std::string where_;
  std::vector<std::string> secrets_;  // scrubbed from every message
};

// The events of a server session from `fromSeq` on, in order, named as session `asSession`
// (the server's id for LabStore, the file's for a pull).
std::vector<Event> readEvents(Connection& c, std::int64_t serverSession, std::int64_t fromSeq, std::int64_t asSession);

// Whether the server's sessions carry `genesis_form` (lab schema 10: a genesis that covers the
// station). Asked of the table, not the recorded version, which tests set back to simulate
// older servers.
bool hasGenesisForms(Connection& c);

}  // namespace leafdig::db::pg
