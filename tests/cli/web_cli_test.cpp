// The web review (`leafdig server web`, docs/web.md) against a real lab server: its API driven
// over HTTP as a script or a page would, as a curator, two technicians and a reader; the role
// limits proven through it as they are through SQL and the CLI; the security the issue asks
// (session cookie, CSRF, cross-site refusal, the same answer for an unknown login and a wrong
// password, rate limits, a strict CSP). The cluster is lab_cli_test.cpp's (one per program).
#include <httplib.h>
#include <signal.h>

#include <chrono>
#include <thread>

#include "../support/station_sessions.hpp"
#include "lab_cli_support.hpp"

namespace {

// A browser as far as the API sees one: a cookie jar of one cookie and the CSRF token.
struct Browser {
  httplib::Client http;
  std::string cookie, csrf;
  explicit Browser(int port) : http("127.0.0.1", port) { http.set_read_timeout(60, 0); }

  httplib::Headers headers(const httplib::Headers& extra = {}) const {
    httplib::Headers h = extra;
    if (!cookie.empty()) h.emplace("Cookie", cookie);
    return h;
  }
  httplib::Result get(const std::string& path) { return http.Get(path.c_str(), headers()); }
  httplib::Result post(const std::string& path, const json& body, httplib::Headers extra = {}, bool withCsrf = true) {
    if (withCsrf && !csrf.empty()) extra.emplace("X-CSRF-Token", csrf);
    return http.Post(path.c_str(), headers(extra), body.dump(), "application/json");
  }
  // Logs in; returns the answer (the cookie and token kept when it is taken).
  httplib::Result login(const std::string& login, const std::string& password) {
    auto r = post("/api/login", json{{"login", login}, {"password", password}}, {}, false);
    if (r && r->status == 200) {
      const std::string set = r->get_header_value("Set-Cookie");
      cookie = set.substr(0, set.find(';'));
      csrf = json::parse(r->body).at("csrf").get<std::string>();
    }
    return r;
  }
};

class WebCli : public LabCli {
 protected:
  void TearDown() override {
    if (server_ > 0) {
      ::kill(server_, SIGTERM);
      EXPECT_EQ(reap(server_), 0) << slurp(dir_ / "web.err");
    }
    LabCli::TearDown();
  }
  // Starts `leafdig server web` on a free port and returns the port it printed.
  int startWeb() {
    const std::string server = "postgresql://127.0.0.1:" + std::to_string(clusterOf().port()) + "/" + database_;
    server_ = spawn({"server", "web", "--db", server, "--listen", "127.0.0.1:0"}, dir_ / "web.out", dir_ / "web.err");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
      const std::string out = slurp(dir_ / "web.out");
      if (const auto at = out.find("http://127.0.0.1:"); at != std::string::npos && out.find('\n') != std::string::npos)
        return std::stoi(out.substr(at + 17));
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ADD_FAILURE() << "leafdig server web printed no address: " << slurp(dir_ / "web.err");
    return 0;
  }
  static std::string passwordOf(const std::string& login) { return "s3cret-" + login; }

  pid_t server_ = -1;
};

TEST_F(WebCli, ACuratorReviewsFromABrowserAndEveryRoleIsHeldToItsLimitsThroughTheApi) {
  ASSERT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
  const std::string techA = "tech_a_" + database_, techB = "tech_b_" + database_;
  const std::string carla = "carla_" + database_, rita = "rita_" + database_;
  const std::string techAUrl = addUser(techA, "technician", "bench-a");
  const std::string techBUrl = addUser(techB, "technician", "bench-b");
  const std::string carlaUrl = addUser(carla, "curator");
  (void)addUser(rita, "reader");
  for (const auto& [station, url] : {std::pair{std::string("bench-a"), techAUrl}, {std::string("bench-b"), techBUrl}}) {
    const fs::path file = dir_ / (station + ".sqlite");
    {
      leafdig::db::Store s(file.string());
      for (int leaf = 1; leaf <= (station == "bench-a" ? 2 : 1); ++leaf)
        (void)leafdig::test::captureSession(s, station, leaf);
    }
    ASSERT_EQ(leafdig("sync push --db " + quote(file) + " --to " + quote(url)).exitCode, 0);
  }
  const int port = startWeb();
  ASSERT_GT(port, 0);

  // The page: one document, its script and style from leafdig itself, a strict CSP.
  Browser anyone(port);
  auto page = anyone.get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_EQ(page->get_header_value("Content-Type").rfind("text/html", 0), 0u);
  const std::string csp = page->get_header_value("Content-Security-Policy");
  EXPECT_NE(csp.find("script-src 'self'"), std::string::npos) << csp;
  EXPECT_NE(csp.find("frame-ancestors 'none'"), std::string::npos) << csp;
  EXPECT_EQ(csp.find("unsafe"), std::string::npos) << csp;
  EXPECT_EQ(page->body.find("<script>"), std::string::npos) << "no inline script";
  EXPECT_EQ(page->body.find("http"), std::string::npos) << "nothing from another origin";
  EXPECT_EQ(anyone.get("/static/app.js")->status, 200);
  // A browser that takes brotli too is answered gzip (docs/web.md, "Sizes and speed").
  const auto three = anyone.http.Get("/static/vendor/three.module.min.js", {{"Accept-Encoding", "gzip, deflate, br"}});
  ASSERT_TRUE(three);
  EXPECT_EQ(three->status, 200);
  EXPECT_EQ(three->get_header_value("Content-Encoding"), "gzip");
  EXPECT_NE(three->body.find("REVISION"), std::string::npos);
  EXPECT_EQ(anyone.get("/static/index.html")->status, 404);
  EXPECT_EQ(anyone.get("/../../etc/passwd")->status, 404);

  // Nothing without a login, in the API's shape.
  auto r = anyone.get("/api/sessions");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 401);
  EXPECT_TRUE(json::parse(r->body).contains("what_to_do")) << r->body;

  // A wrong password and an unknown login: the same status and words.
  auto wrong = Browser(port).login(carla, "not-it");
  auto unknown = Browser(port).login("nobody_" + database_, "not-it");
  ASSERT_TRUE(wrong && unknown);
  EXPECT_EQ(wrong->status, 401);
  EXPECT_EQ(unknown->status, 401);
  EXPECT_EQ(wrong->body, unknown->body);
  EXPECT_EQ(wrong->body.find(carla), std::string::npos) << "the login is not echoed: " << wrong->body;
  // A login as a form (what a cross-site page can post) is refused before it is tried.
  auto form = anyone.http.Post("/api/login", "login=" + carla + "&password=" + passwordOf(carla),
                               "application/x-www-form-urlencoded");
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, 415);

  // The curator.
  Browser curator(port);
  r = curator.login(carla, passwordOf(carla));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const std::string setCookie = r->get_header_value("Set-Cookie");
  EXPECT_NE(setCookie.find("HttpOnly"), std::string::npos) << setCookie;
  EXPECT_NE(setCookie.find("SameSite=Strict"), std::string::npos) << setCookie;
  EXPECT_EQ(r->body.find(passwordOf(carla)), std::string::npos);
  const json me = json::parse(curator.get("/api/me")->body);
  EXPECT_EQ(me.at("login"), carla);
  EXPECT_EQ(me.at("role"), "curator");
  const json all = json::parse(curator.get("/api/sessions")->body);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(json::parse(curator.get("/api/sessions?station=bench-b")->body).size(), 1u);
  EXPECT_EQ(json::parse(curator.get("/api/sessions?status=approved")->body).size(), 0u);
  const std::string id = std::to_string(all[0].at("id").get<std::int64_t>());
  // A session is what `sessions show --json` prints of it.
  const Result cli = leafdig("sessions show " + id + " --json --db " + quote(carlaUrl));
  ASSERT_EQ(cli.exitCode, 0) << cli.err;
  EXPECT_EQ(json::parse(curator.get("/api/sessions/" + id)->body), json::parse(cli.out));
  EXPECT_EQ(curator.get("/api/sessions/99999")->status, 404);
  // Files and numbers: an unknown format named with the ones there are; a leaf without its
  // margin thickness makes no model (409, in words), its metrics say why they are missing.
  r = curator.get("/api/sessions/" + id + "/export?format=exe");
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_NE(json::parse(r->body).at("what_to_do").get<std::string>().find("glb"), std::string::npos) << r->body;
  r = curator.get("/api/sessions/" + id + "/export?format=glb&resolution=huge");
  EXPECT_EQ(r->status, 400) << r->body;
  r = curator.get("/api/sessions/" + id + "/export?format=glb");
  EXPECT_EQ(r->status, 409) << r->body;
  EXPECT_NE(r->body.find("edge_thickness"), std::string::npos) << r->body;
  EXPECT_EQ(curator.get("/api/sessions/" + id + "/surveys")->status, 400);  // a leaf has no surveys
  r = curator.get("/api/sessions/" + id + "/review");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_TRUE(json::parse(r->body).at("metrics").is_null());
  EXPECT_NE(json::parse(r->body).at("metrics_problem").get<std::string>().find("edge_thickness"), std::string::npos);
  EXPECT_EQ(curator.get("/api/sessions/1e3")->status, 404);

  // A decision without the CSRF token, or from another site, changes nothing.
  r = curator.post("/api/sessions/" + id + "/approve", json{{"why", "checked"}}, {}, false);
  EXPECT_EQ(r->status, 403) << r->body;
  r = curator.post("/api/sessions/" + id + "/approve", json{{"why", "checked"}}, {{"Origin", "http://evil.example"}});
  EXPECT_EQ(r->status, 403) << r->body;
  r = curator.http.Post(("/api/sessions/" + id + "/approve").c_str(), curator.headers({{"X-CSRF-Token", curator.csrf}}),
                        "why=checked", "text/plain");
  EXPECT_EQ(r->status, 415) << r->body;
  r = curator.post("/api/sessions/" + id + "/approve", json{{"why", "  "}});
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(json::parse(curator.get("/api/sessions/" + id)->body).at("status"), "complete");
  // The decision, with the token and a reason: the history says who, when and why, as the CLI does.
  r = curator.post("/api/sessions/" + id + "/approve", json{{"why", "checked against the photos"}});
  ASSERT_EQ(r->status, 200) << r->body;
  const json approved = json::parse(r->body);
  EXPECT_EQ(approved.at("status"), "approved");
  ASSERT_FALSE(approved.at("history").empty());
  EXPECT_EQ(approved.at("history").back().at("action"), "approved");
  EXPECT_EQ(approved.at("history").back().at("who"), carla);
  EXPECT_EQ(approved.at("history").back().at("why"), "checked against the photos");
  EXPECT_EQ(json::parse(leafdig("sessions show " + id + " --json --db " + quote(carlaUrl)).out).at("history"),
            approved.at("history"));
  r = curator.post("/api/sessions/" + id + "/approve", json{{"why", "again"}});
  EXPECT_EQ(r->status, 409) << r->body;
  r = curator.post("/api/sessions/" + id + "/reopen", json{{"why", "a point to look at again"}});
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body).at("status"), "complete");

  // A correction: bad numbers refused by name (nothing at JSON's edge gets through), a dry run
  // that says the move and the event it was worked out at, a write refused when the session
  // moved on since, or unconfirmed beyond the limit; then written, and in the history.
  const std::string correctPath = "/api/sessions/" + id + "/correct";
  json fix{{"what", "marker"}, {"row", 2}, {"col", 3}, {"why", "the stylus slipped"}};
  const json shownBefore = json::parse(curator.get("/api/sessions/" + id)->body);
  json at;
  for (const json& m : shownBefore.at("markers"))
    if (m.at("row") == 2 && m.at("col") == 3) at = m.at("position_mm");
  ASSERT_TRUE(at.is_array());
  for (const std::string bad : {R"(["1", 2, 3])", "[1, 2]", "[1e400, 0, 0]", "[1, 2, 3, 4]", "{}"}) {
    json b = fix;
    b["position_mm"] = json::parse(bad, nullptr, false);
    if (b["position_mm"].is_discarded()) b["position_mm"] = nullptr;
    r = curator.http.Post(correctPath.c_str(), curator.headers({{"X-CSRF-Token", curator.csrf}}),
                          R"({"what":"marker","row":2,"col":3,"why":"x","position_mm":)" + bad + "}",
                          "application/json");
    EXPECT_EQ(r->status, 400) << bad << ": " << r->body;
  }
  r = curator.post(correctPath, json{{"what", "nonsense"}, {"why", "x"}, {"position_mm", {1, 2, 3}}});
  EXPECT_EQ(r->status, 400) << r->body;
  fix["position_mm"] = {at[0].get<double>() + 50, at[1], at[2]};
  fix["dry_run"] = true;
  r = curator.post(correctPath, fix);
  ASSERT_EQ(r->status, 200) << r->body;
  const json dry = json::parse(r->body);
  EXPECT_NEAR(dry.at("moved_mm").get<double>(), 50.0, 1e-6);
  EXPECT_TRUE(dry.at("needs_confirm").get<bool>());
  fix.erase("dry_run");
  fix["seen_head"] = dry.at("head");
  r = curator.post(correctPath, fix);
  EXPECT_EQ(r->status, 409) << r->body;
  EXPECT_TRUE(json::parse(r->body).at("needs_confirm").get<bool>());
  fix["seen_head"] = dry.at("head").get<std::int64_t>() - 1;  // the session has moved on since
  fix["confirm"] = true;
  r = curator.post(correctPath, fix);
  EXPECT_EQ(r->status, 409) << r->body;
  EXPECT_EQ(json::parse(curator.get("/api/sessions/" + id)->body).at("events"), shownBefore.at("events"));
  fix["seen_head"] = dry.at("head");
  r = curator.post(correctPath, fix);
  ASSERT_EQ(r->status, 200) << r->body;
  const json corrected = json::parse(r->body).at("history").back();
  EXPECT_EQ(corrected.at("action"), "corrected");
  EXPECT_EQ(corrected.at("who"), carla);
  EXPECT_NEAR(corrected.at("moved_mm").get<double>(), 50.0, 1e-6);

  // A technician sees its own station only and decides nothing: the server refuses, the API says 403.
  Browser tech(port);
  ASSERT_EQ(tech.login(techA, passwordOf(techA))->status, 200);
  EXPECT_EQ(json::parse(tech.get("/api/me")->body).at("role"), "technician");
  const json own = json::parse(tech.get("/api/sessions")->body);
  ASSERT_EQ(own.size(), 2u);
  for (const json& s : own) EXPECT_EQ(s.at("station"), "bench-a");
  const std::string other =
      std::to_string(json::parse(curator.get("/api/sessions?station=bench-b")->body)[0].at("id").get<std::int64_t>());
  EXPECT_EQ(tech.get("/api/sessions/" + other)->status, 404);
  r = tech.post("/api/sessions/" + std::to_string(own[1].at("id").get<std::int64_t>()) + "/approve",
                json{{"why", "mine"}});
  EXPECT_EQ(r->status, 403) << r->body;
  // A reader neither.
  Browser reader(port);
  ASSERT_EQ(reader.login(rita, passwordOf(rita))->status, 200);
  r = reader.post("/api/sessions/" + id + "/reject", json{{"why", "no"}});
  EXPECT_EQ(r->status, 403) << r->body;
  r = reader.post("/api/sessions/" + id + "/correct",
                  json{{"what", "marker"}, {"row", 1}, {"col", 1}, {"why", "x"}, {"position_mm", {1, 2, 3}}});
  EXPECT_EQ(r->status, 403) << r->body;
  EXPECT_EQ(json::parse(reader.get("/api/sessions/" + id)->body).at("status"), "complete");
  // Every role limit above is the server's: the same through plain SQL.
  EXPECT_NE(leafdig::test::Sql(clusterOf().url(rita, passwordOf(rita), database_))
                .error("UPDATE leafdig.sessions SET status = 'approved'"),
            "");

  // Logged out: the cookie is worth nothing, even replayed.
  const std::string replay = curator.cookie;
  ASSERT_EQ(curator.post("/api/logout", json::object())->status, 200);
  curator.cookie = replay;
  EXPECT_EQ(curator.get("/api/me")->status, 401);

  // Refused logins from one address are limited: after five (two above), even the right password waits.
  for (int i = 0; i < 3; ++i) EXPECT_EQ(Browser(port).login(rita, "guess")->status, 401);
  r = Browser(port).login(rita, passwordOf(rita));
  EXPECT_EQ(r->status, 429) << r->body;
  EXPECT_TRUE(json::parse(r->body).contains("what_to_do"));
  // Nothing of any password in the server's output.
  EXPECT_EQ(slurp(dir_ / "web.out").find("s3cret"), std::string::npos);
  EXPECT_EQ(slurp(dir_ / "web.err").find("s3cret"), std::string::npos);
}

// The pages in a real browser (tests/tools/web-review.mjs: Debian's chromium, headless, driven by
// puppeteer-core): a curator logs in, lists, approves a leaf with a reason and sees the history
// say so, opens a plant; a cross-site form post and a change without the CSRF token change
// nothing; a technician lists its own station only and is offered no decision. The screenshots
// are kept in the build's web-screenshots/ for a person to look at.
TEST_F(WebCli, ACuratorAndATechnicianInHeadlessChromium) {
  ASSERT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
  const std::string techA = "tech_a_" + database_, techP = "tech_p_" + database_, carla = "carla_" + database_;
  const std::string techAUrl = addUser(techA, "technician", "bench-a");
  const std::string techPUrl = addUser(techP, "technician", "bench-p");
  const std::string carlaUrl = addUser(carla, "curator");
  const fs::path leaves = dir_ / "bench-a.sqlite", plant = dir_ / "bench-p.sqlite";
  // A whole leaf captured through the simulated devices (its model drawn in 3-D), and one
  // without its margin thickness (no model: the page says why).
  const Result leaf = leafdig("capture --simulate --speed 20 --seed 2 --no-mistakes --station bench-a --db " +
                              quote(leaves) + " --project trial --plant P7 --leaf-position 4 </dev/null");
  ASSERT_EQ(leaf.exitCode, 0) << leaf.err;
  {
    leafdig::db::Store s(leaves.string());
    (void)leafdig::test::captureSession(s, "bench-a", 5);
  }
  const Result captured =
      leafdig("plant capture --simulate --speed 20 --station bench-p --db " + quote(plant) + " </dev/null");
  ASSERT_EQ(captured.exitCode, 0) << captured.err;
  ASSERT_EQ(leafdig("sync push --db " + quote(leaves) + " --to " + quote(techAUrl)).exitCode, 0);
  ASSERT_EQ(leafdig("sync push --db " + quote(plant) + " --to " + quote(techPUrl)).exitCode, 0);
  const json list = json::parse(leafdig("sessions list --json --db " + quote(carlaUrl)).out);
  // The plant, and the simulated leaf (the leaf of more events).
  std::int64_t leafId = 0, plantId = 0, leafEvents = 0;
  for (const json& s : list)
    if (s.at("kind") == "plant") {
      plantId = s.at("id").get<std::int64_t>();
    } else if (s.at("events").get<std::int64_t>() > leafEvents) {
      leafId = s.at("id").get<std::int64_t>();
      leafEvents = s.at("events").get<std::int64_t>();
    }
  ASSERT_GT(leafId, 0) << list.dump();
  ASSERT_GT(plantId, 0);
  const int port = startWeb();
  ASSERT_GT(port, 0);
  const fs::path shots = fs::path(LEAFDIG_CLI).parent_path().parent_path().parent_path() / "web-screenshots";
  fs::create_directories(shots);
  const json config{{"base", "http://127.0.0.1:" + std::to_string(port)},
                    {"curator", {{"login", carla}, {"password", passwordOf(carla)}}},
                    {"technician", {{"login", techA}, {"password", passwordOf(techA)}, {"station", "bench-a"}}},
                    {"leaf", leafId},
                    {"plant", plantId},
                    {"screenshots", shots.string()}};
  const std::string script = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/web-review.mjs";
  const Result browser = run("node " + quote(script) + " " + quote(config.dump()));
  EXPECT_EQ(browser.exitCode, 0) << browser.out << browser.err << "\nthe web server said: " << slurp(dir_ / "web.err");
  EXPECT_NE(browser.out.find("every check passed"), std::string::npos) << browser.out << browser.err;
  // What the browser did is on the server.
  const json shown =
      json::parse(leafdig("sessions show " + std::to_string(leafId) + " --json --db " + quote(carlaUrl)).out);
  EXPECT_EQ(shown.at("status"), "approved");
  EXPECT_EQ(shown.at("history").back().at("who"), carla);
  EXPECT_EQ(json::parse(leafdig("sessions show " + std::to_string(plantId) + " --json --db " + quote(carlaUrl)).out)
                .at("status"),
            "complete");
  for (const char* shot : {"web-login.png", "web-sessions.png", "web-leaf.png", "web-plant.png", "web-technician.png"})
    EXPECT_GT(fs::file_size(shots / shot), 5000u) << shot;
}

}  // namespace
