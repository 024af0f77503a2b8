// A lab server's address as libpq reads it: which texts are one, and the only forms leafdig
// prints or stores. Defined in db/src/pg.cpp, the one file that reads URLs through libpq.
#pragma once

#include <optional>
#include <string>

namespace leafdig::db {

// postgresql://… or postgres://… (a libpq connection URL).
[[nodiscard]] bool isServerUrl(const std::string& text);
// The URL as libpq reads it, with its password and sslpassword (wherever and however written:
// user:PASSWORD@, ?password=, ?pass%77ord=, password = x) replaced by ***: the only form of a
// URL leafdig prints or stores. A URL libpq cannot read is not shown at all (it may hold a
// password); a file's path comes back as it is.
[[nodiscard]] std::string redactUrl(const std::string& url);
// The URL as libpq reads it without its password and sslpassword (a station stores no
// password: it lives in ~/.pgpass); nothing when libpq cannot read it.
[[nodiscard]] std::optional<std::string> urlWithoutSecrets(const std::string& url);

}  // namespace leafdig::db
