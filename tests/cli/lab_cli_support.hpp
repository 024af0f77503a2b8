// The lab CLI tests' fixture: a new database on the program's one PostgreSQL cluster
// (PgClusterEnvironment, registered by lab_cli_test.cpp), logins made through the CLI.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "../support/pg_cluster_environment.hpp"
#include "cli_support.hpp"
#include "leafdig/db/store.hpp"

namespace {

leafdig::test::PgCluster& clusterOf() {
  return leafdig::test::PgClusterEnvironment::cluster();
}

class LabCli : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    database_ = clusterOf().createDatabase();
    admin_ = clusterOf().adminUrl(database_);
  }
  // A login made through the CLI, with its password in a file.
  std::string addUser(const std::string& login, const std::string& role, const std::string& station = "") {
    const std::string password = "s3cret-" + login;
    const fs::path pw = write(login + ".pw", password + "\n");
    const Result r = leafdig("server add-user --url " + quote(admin_) + " --login " + login + " --role " + role +
                             (station.empty() ? "" : " --station " + station) + " --password-file " + quote(pw));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return clusterOf().url(login, password, database_);
  }
  // Every event on the server, per station session, as text; and the same from a file.
  std::map<std::int64_t, std::vector<std::string>> serverHashes(const std::string& url) {
    std::map<std::int64_t, std::vector<std::string>> out;
    for (const auto& r : leafdig::test::Sql(url).rows(
             "SELECT s.station_session_id, e.seq, e.hash, e.prev_hash, e.utc, e.payload_json FROM leafdig.events e "
             "JOIN leafdig.sessions s ON s.id = e.session_id ORDER BY 1, 2"))
      out[std::stoll(r[0])].push_back(r[1] + " " + r[2] + " " + r[3] + " " + r[4] + " " + r[5]);
    return out;
  }
  static std::map<std::int64_t, std::vector<std::string>> fileHashes(const leafdig::db::Store& s) {
    std::map<std::int64_t, std::vector<std::string>> out;
    for (const auto& info : s.sessions())
      for (const auto& e : s.events(info.id))
        out[info.id].push_back(std::to_string(e.seq) + " " + e.hash + " " + e.prevHash + " " + e.utc + " " +
                               e.payloadJson);
    return out;
  }

  std::string database_, admin_;
};

}  // namespace
