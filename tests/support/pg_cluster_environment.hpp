// One throw-away PostgreSQL cluster for a whole GoogleTest program, started before its first
// test and stopped after its last:
//   const auto* env = ::testing::AddGlobalTestEnvironment(new leafdig::test::PgClusterEnvironment);
//   … leafdig::test::PgClusterEnvironment::cluster() …
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "pg_cluster.hpp"

namespace leafdig::test {

class PgClusterEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { instance() = std::make_unique<PgCluster>(); }
  void TearDown() override { instance().reset(); }
  static PgCluster& cluster() { return *instance(); }

 private:
  static std::unique_ptr<PgCluster>& instance() {
    static std::unique_ptr<PgCluster> c;
    return c;
  }
};

}  // namespace leafdig::test
