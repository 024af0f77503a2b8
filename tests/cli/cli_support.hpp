// The command-line test fixture: runs `leafdig` as a user would (shell, files, exit codes).
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Result {
  int exitCode;
  std::string out;
  std::string err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The JSON lines a command printed; a line cut by kill -9 is not an acknowledgement.
inline std::vector<json> jsonLines(const std::string& text) {
  std::vector<json> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    try {
      out.push_back(json::parse(line));
    } catch (const json::parse_error&) {
    }
  }
  return out;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("leafdig-cli-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::string& commandLine) {
    const fs::path out = dir_ / "stdout.txt";
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = commandLine + " >" + quote(out) + " 2>" + quote(err);
    const int status = std::system(cmd.c_str());
    const Result r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  // One leafdig command; one that never ends (a capture that never completes) is stopped after
  // 800 s — before ctest's 900 s would stop the whole test binary without its output — and its
  // Result says so.
  Result leafdig(const std::string& args) {
    Result r = run("timeout --foreground --kill-after=5 800 " + quote(LEAFDIG_CLI) + " " + args);
    if (r.exitCode == 124) r.err += "\n(the test stopped this leafdig command after 800 s: it never finished)";
    return r;
  }

  // Starts leafdig in the background with stdout/stderr to files and stdin from /dev/null
  // (for tests that kill it at a chosen instant); reap() waits for it.
  pid_t spawn(const std::vector<std::string>& args, const fs::path& out, const fs::path& err) {
    std::vector<std::string> all{LEAFDIG_CLI};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, LEAFDIG_CLI, &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    EXPECT_EQ(rc, 0);
    return pid;
  }
  static int reap(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
  }
  // `leafdig args` (with --json) killed with SIGKILL once its JSON lines satisfy `enough` (it
  // has printed them, so they are committed): mid-capture by construction, not by a timer.
  // Its JSON lines.
  std::vector<json> killWhen(const std::vector<std::string>& args,
                             const std::function<bool(const std::vector<json>&)>& enough, const fs::path& out,
                             const fs::path& err) {
    const pid_t pid = spawn(args, out, err);
    const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!enough(jsonLines(slurp(out))) && std::chrono::steady_clock::now() < giveUp)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ::kill(pid, SIGKILL);
    reap(pid);
    return jsonLines(slurp(out));
  }
  // …once it has printed k + 1 lines: after its k-th acknowledged event.
  std::vector<json> killAfterLines(const std::vector<std::string>& args, std::size_t k, const fs::path& out,
                                   const fs::path& err) {
    return killWhen(
        args, [k](const std::vector<json>& lines) { return lines.size() >= k + 1; }, out, err);
  }

  static std::string sample(const std::string& name) {
    return std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/" + name;
  }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  json sampleJson() { return json::parse(slurp(sample("lower-leaf-n10.markers.json"))); }

  // Runs `model build` on a bad file and checks it fails with exit code 2, a message that
  // names `where` and `what`, and writes nothing.
  void expectBadInput(const std::string& text, const std::string& where, const std::string& what) {
    const fs::path in = write("bad.markers.json", text);
    const fs::path out = dir_ / "out.glb";
    const fs::path model = dir_ / "out.model.json";
    const Result r = leafdig("model build " + quote(in) + " -o " + quote(out) + " --model-json " + quote(model));
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find(where), std::string::npos) << "message should name \"" << where << "\": " << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << "message should say \"" << what << "\": " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(model));
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir_)) files += e.path().filename() != "bad.markers.json";
    EXPECT_EQ(files, 0u) << "nothing may be written on bad input";
  }

  fs::path dir_;
};

}  // namespace
