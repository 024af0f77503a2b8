// `leafdig capture --simulate`, `leafdig sessions …` and `leafdig demo` driven as a script
// and a curator would: the JSON-lines contract, kill -9 at random instants, unplugs,
// foreign databases, review and export.
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "../support/strict_formats.hpp"
#include "cli_support.hpp"

namespace {

// The items a script may rely on: accepted and not undone (by seq).
std::map<std::int64_t, json> acknowledged(const std::vector<json>& lines) {
  std::map<std::int64_t, json> items;
  for (const json& j : lines) {
    const std::string e = j.at("event");
    if (e == "accepted" || e == "retake_cancelled") items[j.at("seq").get<std::int64_t>()] = j;
    if (e == "undone" || e == "retake") items.erase(j.at("seq").get<std::int64_t>());
  }
  return items;
}

class CaptureCli : public Cli {
 protected:
  json show(const fs::path& db, std::int64_t id) {
    const Result r = leafdig("sessions show " + std::to_string(id) + " --db " + quote(db) + " --json");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return json::parse(r.out);
  }
  // Session 1 of `db` is complete with `markers` markers, and every item the capture's JSON
  // lines acknowledged is stored once.
  void expectCapturedWhole(const fs::path& db, const std::vector<json>& lines, std::size_t markers) {
    const json shown = show(db, 1);
    EXPECT_EQ(shown.at("status"), "complete");
    EXPECT_EQ(shown.at("markers").size(), markers);
    expectAllAcknowledgedStored(acknowledged(lines), shown);
  }
  // How many JSON lines of this event say `words` in their `field`.
  static int countSaying(const std::vector<json>& lines, const std::string& event, const std::string& field,
                         const std::string& words) {
    int n = 0;
    for (const json& j : lines)
      n += j.at("event") == event && j.at(field).get<std::string>().find(words) != std::string::npos;
    return n;
  }
  // Whether the store holds an undo (or retake) of the item accepted by event `seq`: a kill
  // can fall between committing the operator's undo and printing it. Read with Python's
  // sqlite3, as another program reads the station's file.
  bool takenOutAfterwards(const fs::path& db, std::int64_t session, std::int64_t seq) {
    const Result r =
        run("python3 -c \"import json, sqlite3, sys; c = sqlite3.connect('file:' + sys.argv[1] + '?mode=ro', "
            "uri=True); print(sum(1 for k, p in c.execute('SELECT kind, payload_json FROM events WHERE "
            "session_id=' + sys.argv[2]) if k in ('undone', 'retake') and json.loads(p).get('seq') == "
            "int(sys.argv[3])))\" " +
            quote(db) + " " + std::to_string(session) + " " + std::to_string(seq));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.out.find('1') == 0;
  }
  // How far the farthest marker of an exported leaf taken on the simulated board (its origin at
  // (-150, -150, -5) of the file's frame, its axes the file's) lies from the file's; a leaf with
  // another count of rows is infinitely far.
  static double worstMarkerOffTheBoardFileMm(const fs::path& exported, const std::string& file) {
    const json got = json::parse(slurp(exported));
    const json want = json::parse(slurp(file));
    if (got.at("rows").size() != want.at("rows").size()) return std::numeric_limits<double>::infinity();
    double worst = 0;
    for (std::size_t row = 0; row < want["rows"].size(); ++row)
      for (std::size_t col = 0; col < 7; ++col) {
        const json& a = got["rows"][row]["points"][col];
        const json& b = want["rows"][row]["points"][col];
        worst = std::max(worst, std::hypot(a[0].get<double>() - 150.0 - b[0].get<double>(),
                                           a[1].get<double>() - 150.0 - b[1].get<double>(),
                                           a[2].get<double>() - 5.0 - b[2].get<double>()));
      }
    return worst;
  }
  // Every acknowledged item is in the store exactly once, with the value that was printed;
  // with `db`, an item whose undo was committed but not yet printed may be absent.
  void expectAllAcknowledgedStored(const std::map<std::int64_t, json>& acks, const json& shown, const fs::path& db = {},
                                   std::int64_t session = 0) {
    std::multiset<std::string> stored;
    const auto key = [](const std::string& what, const json& row, const json& col) {
      return what + "/" + (row.is_null() ? "-" : std::to_string(row.get<int>())) + "/" +
             (col.is_null() ? "-" : std::to_string(col.get<int>()));
    };
    if (!shown.at("tip").is_null()) stored.insert("tip/-/-");
    for (const auto& m : shown.at("markers")) stored.insert(key("marker", m.at("row"), m.at("col")));
    for (const auto& t : shown.at("thickness")) stored.insert(key(t.at("what"), t.at("row"), t.at("col")));
    for (const auto& b : shown.value("board", json::array())) stored.insert(key("board", nullptr, b.at("col")));
    for (const auto& b : shown.value("board_again", json::array()))
      stored.insert(key("board_again", b.at("relocation"), b.at("col")));
    for (const auto& [seq, a] : acks) {
      const std::string k = key(a.at("what"), a.at("row"), a.at("col"));
      if (stored.count(k) == 0 && !db.empty() && takenOutAfterwards(db, session, seq)) continue;
      EXPECT_EQ(stored.count(k), 1u) << "acknowledged " << a.dump() << " must be stored exactly once";
      if (a.at("what") == "tip") {
        EXPECT_EQ(shown.at("tip"), a.at("value"));
      }
      if (a.at("what") == "marker")
        for (const auto& m : shown.at("markers"))
          if (m.at("row") == a.at("row") && m.at("col") == a.at("col")) {
            EXPECT_EQ(m.at("position_mm"), a.at("value"));
          }
    }
    // And nothing more than what replays from the log.
    EXPECT_EQ(stored.size(), static_cast<std::size_t>(shown.at("markers").size() + shown.at("thickness").size() +
                                                      (shown.at("tip").is_null() ? 0 : 1) +
                                                      shown.value("board", json::array()).size() +
                                                      shown.value("board_again", json::array()).size()));
  }
};

TEST_F(CaptureCli, ASimulatedCaptureFollowsTheJsonLinesContractAndEveryLineIsInTheStore) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("capture --simulate --speed 8 --seed 3 --json --db " + quote(db) +
                           " --project trial --plant P7 --leaf-position 4 --operator ana </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto lines = jsonLines(r.out);
  ASSERT_GT(lines.size(), 80u);
  EXPECT_EQ(lines.front(), (json{{"event", "session"}, {"session", 1}}));
  std::set<std::string> whats, reasons;
  std::int64_t lastSeq = 0;
  for (const json& j : lines) {
    const std::string e = j.at("event");
    if (e == "accepted") {
      whats.insert(j.at("what").get<std::string>());
      EXPECT_GT(j.at("seq").get<std::int64_t>(), lastSeq);
      lastSeq = j.at("seq");
      if (j.at("what") == "marker") {
        EXPECT_GE(j.at("row").get<int>(), 1);
        EXPECT_GE(j.at("col").get<int>(), 1);
        EXPECT_LE(j.at("col").get<int>(), 7);
        EXPECT_EQ(j.at("value").size(), 3u);
      } else if (j.at("what") != "tip") {
        EXPECT_TRUE(j.at("value").is_number());
      }
    }
    if (e == "rejected") reasons.insert(j.at("reason").get<std::string>());
    if (e == "prompt") {
      EXPECT_FALSE(j.at("text").get<std::string>().empty());
    }
  }
  EXPECT_EQ(whats,
            (std::set<std::string>{"tip", "marker", "midrib_thickness", "vein_origin_thickness", "edge_thickness"}));
  // The virtual operator's mistakes were caught and said in words.
  const auto said = [&](const std::string& words) {
    for (const auto& x : reasons)
      if (x.find(words) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(said("double press")) << json(reasons).dump();
  EXPECT_TRUE(said("uneven spacing")) << json(reasons).dump();
  EXPECT_TRUE(said("outside")) << json(reasons).dump();
  bool undone = false;
  for (const json& j : lines) undone = undone || j.at("event") == "undone";
  EXPECT_TRUE(undone);
  EXPECT_EQ(lines.back().at("event"), "prompt");
  EXPECT_EQ(lines[lines.size() - 2],
            (json{{"event", "complete"}, {"session", 1}, {"seq", lines[lines.size() - 2].at("seq")}}));

  const json shown = show(db, 1);
  EXPECT_EQ(shown.at("status"), "complete");
  EXPECT_EQ(shown.at("chain_ok"), true);
  EXPECT_EQ(shown.at("markers").size(), 70u);
  EXPECT_EQ(shown.at("thickness").size(), 21u);
  EXPECT_EQ(shown.at("step").at("what"), "done");
  expectAllAcknowledgedStored(acknowledged(lines), shown);

  // Review and export, as a curator.
  EXPECT_EQ(leafdig("sessions approve 1 --db " + quote(db)).exitCode, 2) << "--who is required";
  EXPECT_EQ(leafdig("sessions reject 1 --who bo --db " + quote(db)).exitCode, 2);
  // A correction first: through the CLI, with a reason, stored as an event.
  EXPECT_EQ(leafdig("sessions correct 1 --what midrib_thickness --row 1 --col 4 --value 1.5 --who bo --db " + quote(db))
                .exitCode,
            2)
      << "--why is required";
  const Result bad = leafdig(
      "sessions correct 1 --what midrib_thickness --row 1 --col 4 --value 150 --who bo "
      "--why 'jaws slipped' --db " +
      quote(db));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("millimetres"), std::string::npos) << bad.err;
  const Result fixed = leafdig(
      "sessions correct 1 --what midrib_thickness --row 1 --col 4 --value 1.5 --who bo "
      "--why 'jaws slipped' --json --db " +
      quote(db));
  ASSERT_EQ(fixed.exitCode, 0) << fixed.err;
  EXPECT_EQ(json::parse(fixed.out).at("corrected"), "midrib_thickness");
  bool corrected = false;
  const json readings = show(db, 1).at("thickness");
  for (const json& t : readings)
    corrected = corrected || (t.at("what") == "midrib_thickness" && t.at("row") == 1 && t.at("value_mm") == 1.5);
  EXPECT_TRUE(corrected) << readings.dump();
  const Result ok = leafdig("sessions approve 1 --who bo --why 'checked' --db " + quote(db));
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
  EXPECT_EQ(show(db, 1).at("status"), "approved");
  const Result ex = leafdig("sessions export 1 --out " + quote(dir_ / "x") + " --db " + quote(db) + " --json");
  ASSERT_EQ(ex.exitCode, 0) << ex.err;
  EXPECT_EQ(json::parse(ex.out).at("outputs").size(), 9u);
  // --node is for a plant session's leaves.
  const Result node = leafdig("sessions export 1 --node 2 --out " + quote(dir_ / "n") + " --db " + quote(db));
  EXPECT_EQ(node.exitCode, 2);
  EXPECT_NE(node.err.find("captured one leaf: --node names a full leaf of a plant session"), std::string::npos)
      << node.err;
  EXPECT_FALSE(fs::exists(dir_ / "n"));
  // The leaf's numbers in one row: its area, interval, silhouette and STAR with the metrics.
  const json exported = json::parse(ex.out).at("metrics");
  // Each CSV opens with where it came from (issue 49), as `#` lines before its header.
  const auto data = [](const std::string& csv) {
    std::size_t at = 0;
    while (at < csv.size() && csv[at] == '#') at = csv.find('\n', at) + 1;
    return csv.substr(at);
  };
  const std::string meFile = slurp(dir_ / "x" / "session-1.metrics.csv");
  EXPECT_EQ(meFile.rfind("# session: 1\n# station: ", 0), 0U) << meFile.substr(0, 300);
  EXPECT_NE(meFile.find("\n# status: approved\n# operator: "), std::string::npos) << meFile.substr(0, 300);
  EXPECT_NE(meFile.find("\n# decision: approved\n# curator: bo\n# decided_utc: 20"), std::string::npos)
      << meFile.substr(0, 300);
  EXPECT_NE(meFile.find("\n# corrections: 1\n"), std::string::npos) << meFile.substr(0, 300);
  // …and so do the model JSON, the OBJ's and PLY's comments and the GLB's asset.extras.
  const json model = json::parse(slurp(dir_ / "x" / "session-1.model.json"));
  EXPECT_EQ(model.at("provenance").at("curator"), "bo");
  EXPECT_EQ(model.at("provenance").at("decision"), "approved");
  EXPECT_EQ(model.at("provenance").at("session"), "1");
  EXPECT_NE(slurp(dir_ / "x" / "session-1.obj").find("\n# provenance curator: bo\n"), std::string::npos);
  EXPECT_NE(slurp(dir_ / "x" / "session-1.ply").find("\ncomment provenance curator: bo\n"), std::string::npos);
  const std::string glb = slurp(dir_ / "x" / "session-1.glb");
  const std::uint32_t jsonLength = static_cast<std::uint32_t>(static_cast<unsigned char>(glb[12])) |
                                   static_cast<std::uint32_t>(static_cast<unsigned char>(glb[13])) << 8 |
                                   static_cast<std::uint32_t>(static_cast<unsigned char>(glb[14])) << 16 |
                                   static_cast<std::uint32_t>(static_cast<unsigned char>(glb[15])) << 24;
  const json gltf = json::parse(glb.substr(20, jsonLength));
  EXPECT_EQ(gltf.at("asset").at("extras").at("provenance").at("curator"), "bo") << gltf.at("asset").dump();
  const std::string me = data(meFile);
  EXPECT_EQ(me.substr(0, me.find('\n')),
            "session,rows,blade_area_mm2,area_low95_mm2,area_high95_mm2,projected_area_mm2,silhouette_mm2,star,"
            "mesh_area_mm2,measured_area_mm2,margin");
  EXPECT_NE(me.find("\n1,10,"), std::string::npos) << me;
  EXPECT_GT(exported.at("star").get<double>(), 0.0);
  EXPECT_NE(me.find("not declared"), std::string::npos) << me;
  const std::string csv = data(slurp(dir_ / "x" / "session-1.markers.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 71);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "session,seq,what,row,col,x_mm,y_mm,z_mm");
  const std::string th = data(slurp(dir_ / "x" / "session-1.thickness.csv"));
  EXPECT_EQ(std::count(th.begin(), th.end(), '\n'), 1 + 21);
  // The exported marker set builds again with the geometry core; assimp opens the OBJ.
  EXPECT_EQ(leafdig("model build " + quote(dir_ / "x" / "session-1.markers.json")).exitCode, 0);
  EXPECT_EQ(run("assimp info " + quote(dir_ / "x" / "session-1.obj")).exitCode, 0);
  const Result verify = leafdig("sessions verify --db " + quote(db) + " --json");
  EXPECT_EQ(verify.exitCode, 0);
  EXPECT_EQ(json::parse(verify.out)[0].at("chain_ok"), true);
}

// LEAFDIG_KILL_RUNS sets the number of runs: 200 in the ci preset, 50 under ASan, 1000 with
// `scripts/kill-test.sh --long` (docs/benchmarks.md has the result).
TEST_F(CaptureCli, KillNineAtRandomInstantsLosesNothingAcknowledgedAndResumeContinuesAtTheExactStep) {
  const fs::path db = dir_ / "station.sqlite";
  std::mt19937 rng(20261121);
  std::uniform_int_distribution<int> killAfterMs(100, 900);
  const char* runsEnv = std::getenv("LEAFDIG_KILL_RUNS");
  const int runs = runsEnv ? std::max(1, std::atoi(runsEnv)) : 200;
  // Kill instants from what the run shows, not from the machine's speed (issue 26): every
  // other run waits for its k-th acknowledged item (k random) and is killed then, in the
  // middle of the capture by construction; the others at a random instant. Every run goes at
  // speed 50 (the instants of 150–2 500 ms at speed 15 become 100–900 ms: the same stretch of
  // the leaf) so that two hundred runs stay a few minutes of CI, not ten.
  std::uniform_int_distribution<int> itemsFirst(1, 40);
  int withItems = 0, killedAfterItems = 0, waitedForItems = 0;
  for (int run = 0; run < runs; ++run) {
    const fs::path out = dir_ / "out.jsonl", err = dir_ / "err.txt";
    const bool waitForItems = run % 2 == 0;
    const pid_t pid = spawn({"capture", "--simulate", "--speed", "50", "--seed", std::to_string(run + 1), "--json",
                             "--db", db.string(), "--leaf-position", std::to_string(run + 1)},
                            out, err);
    if (waitForItems) {
      ++waitedForItems;
      const auto items = static_cast<std::size_t>(itemsFirst(rng));
      const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(120);
      while (acknowledged(jsonLines(slurp(out))).size() < items && std::chrono::steady_clock::now() < giveUp)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(killAfterMs(rng)));
    }
    ::kill(pid, SIGKILL);
    reap(pid);
    const auto lines = jsonLines(slurp(out));
    if (lines.empty()) continue;  // killed before the session existed: nothing was promised
    const std::int64_t id = lines.front().at("session");
    const auto acks = acknowledged(lines);
    withItems += !acks.empty();
    killedAfterItems += waitForItems && !acks.empty();
    const json shown = show(db, id);
    ASSERT_EQ(shown.at("chain_ok"), true) << "run " << run;
    expectAllAcknowledgedStored(acks, shown, db, id);
    if (HasFailure()) FAIL() << "run " << run << ": " << slurp(out);
    // Resume begins exactly at the stored step (the first prompt it prints).
    if (shown.at("status") != "open") continue;
    const pid_t again = spawn({"sessions", "resume", std::to_string(id), "--simulate", "--speed", "50", "--seed",
                               std::to_string(run + 100), "--json", "--db", db.string()},
                              out, err);
    std::string firstPrompt;
    // Up to 10 s for the first prompt: a loaded machine opens and replays slowly (the
    // 1 000-run mode under a parallel build once needed more than 2 s).
    for (int i = 0; i < 1000 && firstPrompt.empty(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      for (const json& j : jsonLines(slurp(out)))
        if (j.at("event") == "prompt") {
          firstPrompt = j.at("text");
          break;
        }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(killAfterMs(rng) / 3));
    ::kill(again, SIGKILL);
    reap(again);
    EXPECT_EQ(firstPrompt, shown.at("step").at("prompt").get<std::string>()) << "run " << run;
    // What the resumed run acknowledged before its own kill is stored too.
    const json after = show(db, id);
    EXPECT_EQ(after.at("chain_ok"), true);
    auto both = acks;
    for (const auto& [seq, j] : acknowledged(jsonLines(slurp(out)))) both[seq] = j;
    for (const json& j : jsonLines(slurp(out)))
      if (j.at("event") == "undone" || j.at("event") == "retake") both.erase(j.at("seq").get<std::int64_t>());
    expectAllAcknowledgedStored(both, after, db, id);
    if (HasFailure()) FAIL() << "run " << run << " (resumed): " << slurp(out);
  }
  EXPECT_EQ(killedAfterItems, waitedForItems) << "a run killed after its first items was killed mid-capture";
  std::printf("kill -9: %d runs, %d killed mid-capture, every acknowledged item stored\n", runs, withItems);
  // Finally one interrupted session is resumed to the end.
  const json list = json::parse(leafdig("sessions list --json --db " + quote(db)).out);
  std::int64_t open = 0;
  for (const auto& s : list)
    if (s.at("status") == "open" && s.at("events").get<int>() > 20) open = s.at("id");
  ASSERT_NE(open, 0);
  const Result done = leafdig("sessions resume " + std::to_string(open) + " --simulate --speed 50 --json --db " +
                              quote(db) + " </dev/null");
  ASSERT_EQ(done.exitCode, 0) << done.err;
  const json finished = show(db, open);
  EXPECT_EQ(finished.at("status"), "complete");
  EXPECT_EQ(finished.at("markers").size(), 70u);
  EXPECT_EQ(finished.at("thickness").size(), 21u);
}

TEST_F(CaptureCli, AnUnpluggedDigitizerMidRowIsReportedAndTheCaptureCarriesOnAtTheSameStep) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r =
      leafdig("capture --simulate --speed 12 --no-mistakes --faults unplug=0.0006:0.3,seed=5 --json --db " + quote(db) +
              " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto lines = jsonLines(r.out);
  int lost = 0;
  for (const json& j : lines)
    if (j.at("event") == "device" && j.at("message").get<std::string>().find("FASTRAK") != std::string::npos &&
        j.at("message").get<std::string>().find("ready") == std::string::npos &&
        j.at("message").get<std::string>().find("connecting") == std::string::npos)
      ++lost;
  EXPECT_GT(lost, 0) << r.out;
  expectCapturedWhole(db, lines, 70);
}

// A FASTRAK that resets now and then: its stream stops and the station re-initialises it. A
// reset while the button was down used to end that press only when the stream came back, as
// long as the outage — the very long press that undoes — so the last point was undone
// unasked, and the simulated technician, pressing the next marker where the station now asked
// again for the undone one, was refused for ever (this leaf, seed 1, never completed). The cut
// press is refused in words; nothing is undone that the technician did not undo.
TEST_F(CaptureCli, ADigitizerResetUnderAPressCutsThePressInWordsAndTheCaptureCompletes) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r =
      leafdig("capture --simulate --speed 15 --seed 1 --no-mistakes --faults reset=0.001 --json --db " + quote(db) +
              " --markers " + quote(sample("upper-small-leaf-n17.markers.json")) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const auto lines = jsonLines(r.out);
  EXPECT_GT(countSaying(lines, "device", "message", "re-initialising"), 0) << r.out;
  // How many presses the resets cut depends on where the technician's gestures fall against
  // the resets, which a loaded host moves: here 1–3 a run, but none is possible, so it is
  // recorded, not asserted (the engine tests cut a press on purpose). Each says what to do.
  const int cut = countSaying(lines, "rejected", "reason", "the digitizer connected again");
  EXPECT_EQ(
      countSaying(lines, "rejected", "reason", "(a reset or an unplug cut it): the press was not taken; press again"),
      cut);
  RecordProperty("presses_cut", cut);
  int undone = 0;
  for (const json& j : lines) undone += j.at("event") == "undone";
  EXPECT_EQ(undone, 0) << r.out;
  expectCapturedWhole(db, lines, 119);
}

// A simulated capture that gets nowhere — here a FASTRAK whose every record carries a status
// letter, so every press is refused — is stopped after --give-up-after seconds, in words that
// say where it stood and what was refused last, and kept; it is never waited on for ever.
TEST_F(CaptureCli, ASimulatedCaptureThatGetsNowhereIsStoppedInWordsAndKept) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r =
      leafdig("capture --simulate --speed 15 --no-mistakes --faults status=1:x --give-up-after 5 --json --db " +
              quote(db) + " </dev/null");
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("the simulated technician got nowhere for 5 s at 'Tip: touch the leaf tip and press'"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("inputs refused since the last accepted one; the last: 'the digitizer reported status 'x'"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("leafdig sessions show 1"), std::string::npos) << r.err;
  const json shown = show(db, 1);
  EXPECT_EQ(shown.at("status"), "open");  // kept, to be resumed or looked at
  EXPECT_EQ(leafdig("capture --simulate --give-up-after 0 --db " + quote(dir_ / "x.sqlite")).exitCode, 2);
}

// Issue 26: records delivered in delayed bursts (the simulated FASTRAK holds its output back
// a quarter of a second now and then, as a busy station PC or a USB-serial adapter does, and
// then sends it all at once). Timed by arrival, an ordinary press straddling a burst looked
// held and ended the rows early; timed by the FASTRAK's own record clock, every press is the
// length it was and the leaf is captured whole.
TEST_F(CaptureCli, PressesAreTimedByTheDevicesClockWhenItsRecordsArriveInDelayedBursts) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("capture --simulate --speed 10 --no-mistakes --faults delay=0.004:0.25,seed=3 --json --db " +
                           quote(db) + " --markers " + quote(sample("lower-leaf-n10.markers.json")) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto lines = jsonLines(r.out);
  int rowsEnded = 0;
  for (const json& j : lines) rowsEnded += j.at("event") == "rows_ended";
  EXPECT_EQ(rowsEnded, 1) << "one end of the rows, the virtual technician's own long press";
  const json shown = show(db, 1);
  EXPECT_EQ(shown.at("status"), "complete");
  EXPECT_EQ(shown.at("markers").size(), 70u) << "all 10 rows";
  expectAllAcknowledgedStored(acknowledged(lines), shown);
}

// A leaf on a board that turns 30° while its rows are taken, with a reference receiver fixed to
// the board (issue 29): every marker is where it is on the leaf — the distance between any two
// markers of neighbouring rows is the file's, within the stylus' noise — while the turn moved
// the leaf's far markers by centimetres under the transmitter.
TEST_F(CaptureCli, ALeafOnATurningBoardUnderAReferenceReceiverKeepsItsShape) {
  const fs::path db = dir_ / "station.sqlite";
  const std::string file = sample("lower-leaf-n10.markers.json");
  const Result r = leafdig("capture --simulate --speed 10 --seed 2 --reference-receiver --pot-turn 30 --json --db " +
                           quote(db) + " --markers " + quote(file) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  expectAllAcknowledgedStored(acknowledged(jsonLines(r.out)), show(db, 1));
  ASSERT_EQ(leafdig("sessions export 1 --format markers --out " + quote(dir_) + " --db " + quote(db)).exitCode, 0);
  const json got = json::parse(slurp(dir_ / "session-1.markers.json"));
  const json want = json::parse(slurp(file));
  ASSERT_EQ(got.at("rows").size(), want.at("rows").size());
  const auto point = [](const json& rows, std::size_t row, std::size_t col) {
    const json& p = rows[row]["points"][col];
    return std::array<double, 3>{p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
  };
  const auto distance = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  };
  double worst = 0;
  int pairs = 0;
  for (std::size_t row = 0; row + 1 < got["rows"].size(); ++row)
    for (std::size_t a = 0; a < 7; ++a)
      for (std::size_t b = 0; b < 7; ++b) {
        const double d = distance(point(got["rows"], row, a), point(got["rows"], row + 1, b)) -
                         distance(point(want["rows"], row, a), point(want["rows"], row + 1, b));
        worst = std::max(worst, std::abs(d));
        ++pairs;
      }
  EXPECT_EQ(pairs, 9 * 49);
  EXPECT_LT(worst, 1.5) << "a marker moved on the leaf";
  // The pot turns only under a reference receiver, and only in a simulation.
  const Result alone = leafdig("capture --simulate --pot-turn 30 --db " + quote(dir_ / "other.sqlite") + " </dev/null");
  EXPECT_EQ(alone.exitCode, 2);
  EXPECT_NE(alone.err.find("goes with --simulate --reference-receiver"), std::string::npos) << alone.err;
  EXPECT_FALSE(fs::exists(dir_ / "other.sqlite"));
}

// A leaf captured through a bent field (issue 50, `--distortion`): every marker is reported
// where the field puts it — here a field that moves every point 3 mm along x, 2 mm back along y
// and 1 mm up — and a file that is not a field, or a field without --simulate, is refused in
// words before anything is captured.
TEST_F(CaptureCli, ALeafCapturedThroughADistortedFieldIsWhereTheFieldPutsIt) {
  const fs::path field = dir_ / "uniform.field.json";
  {
    json d = json::array();
    for (int i = 0; i < 8; ++i) d.push_back({3, -2, 1});
    std::ofstream(field) << json{
        {"format", "leafdig.field-distortion/1"},
        {"units", "mm"},
        {"frame", "transmitter"},
        {"origin", {-1000, -1000, -1000}},
        {"spacing_mm", 1000},
        {"shape", {2, 2, 2}},
        {"displacement_mm", d}}.dump();
  }
  const fs::path db = dir_ / "station.sqlite";
  const std::string file = sample("lower-leaf-n10.markers.json");
  const Result r = leafdig("capture --simulate --speed 12 --seed 4 --no-mistakes --json --distortion " + quote(field) +
                           " --db " + quote(db) + " --markers " + quote(file) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_EQ(leafdig("sessions export 1 --format markers --frame digitizer --out " + quote(dir_) + " --db " + quote(db))
                .exitCode,
            0);
  const json got = json::parse(slurp(dir_ / "session-1.markers.json"));
  const json want = json::parse(slurp(file));
  ASSERT_EQ(got.at("rows").size(), want.at("rows").size());
  std::array<double, 3> mean{0, 0, 0};
  int n = 0;
  for (std::size_t row = 0; row < want["rows"].size(); ++row)
    for (std::size_t col = 0; col < want["rows"][row]["points"].size(); ++col, ++n)
      for (std::size_t a = 0; a < 3; ++a)
        mean[a] += got["rows"][row]["points"][col][a].get<double>() - want["rows"][row]["points"][col][a].get<double>();
  ASSERT_GT(n, 60);
  EXPECT_NEAR(mean[0] / n, 3.0, 0.2);
  EXPECT_NEAR(mean[1] / n, -2.0, 0.2);
  EXPECT_NEAR(mean[2] / n, 1.0, 0.2);
  // The steel-bench preset is read as shipped; a file that is not a field is refused by name.
  const Result bench = leafdig("capture --simulate --speed 12 --no-mistakes --distortion " +
                               quote(fs::path(LEAFDIG_SOURCE_DIR) / "data/fields/steel-bench.field.json") + " --db " +
                               quote(dir_ / "bench.sqlite") + " </dev/null");
  EXPECT_EQ(bench.exitCode, 0) << bench.err;
  const Result notAField = leafdig("capture --simulate --distortion " + quote(file) + " --db " +
                                   quote(dir_ / "other.sqlite") + " </dev/null");
  EXPECT_EQ(notAField.exitCode, 2);
  EXPECT_NE(notAField.err.find("lower-leaf-n10.markers.json: "), std::string::npos) << notAField.err;
  EXPECT_NE(notAField.err.find("leafdig field model steel-bench"), std::string::npos) << notAField.err;
  const Result real = leafdig("capture --digitizer fastrak:/dev/null --caliper sylvac:/dev/null --distortion " +
                              quote(field) + " --db " + quote(dir_ / "real.sqlite") + " </dev/null");
  EXPECT_EQ(real.exitCode, 2);
  EXPECT_NE(real.err.find("it goes with --simulate"), std::string::npos) << real.err;
  EXPECT_FALSE(fs::exists(dir_ / "real.sqlite"));
  // The device simulator takes it for a magnetic tracker only.
  const Result arm =
      leafdig("sim microscribe --seconds 1 --markers " + quote(file) + " --distortion " + quote(field) + " </dev/null");
  EXPECT_EQ(arm.exitCode, 2);
  EXPECT_NE(arm.err.find("bends a magnetic tracker's field"), std::string::npos) << arm.err;
}

// A leaf captured across a move of the transmitter (issue 29, `--relocate-source-after`): after
// 12 points the simulated transmitter moves to a seeded random pose (up to 150 mm and 40°), the
// virtual technician takes the board's three points again, and the fit takes every later point
// back into the first position's frame — every marker within the stylus' noise of the file,
// where without the fit 59 of them would be off by centimetres.
TEST_F(CaptureCli, ALeafTakenAcrossAMoveOfTheTransmitterIsTheSameLeaf) {
  const fs::path db = dir_ / "station.sqlite";
  const std::string file = sample("lower-leaf-n10.markers.json");
  const Result r = leafdig("capture --simulate --speed 20 --seed 3 --relocate-source-after 12 --json --db " +
                           quote(db) + " --markers " + quote(file) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto lines = jsonLines(r.out);
  std::vector<std::string> steps;
  for (const json& j : lines)
    if (j.at("event") == "relocation") {
      steps.push_back(j.at("step").get<std::string>());
      if (steps.back() == "fitted") {
        EXPECT_LT(j.at("rms_mm").get<double>(), 1.0) << j.dump();
      }
    }
  EXPECT_EQ(steps, (std::vector<std::string>{"started", "fitted"}));
  const json shown = show(db, 1);
  EXPECT_EQ(shown.at("status"), "complete");
  EXPECT_EQ(shown.at("markers").size(), 70u) << "the board points taken again are not markers";
  EXPECT_EQ(shown.at("board_again").size(), 3u);
  ASSERT_EQ(shown.at("transmitter_positions").size(), 2u);
  EXPECT_GT(shown["transmitter_positions"][1].at("points").get<int>(), 50);
  int fromTheMove = 0;
  for (const json& m : shown.at("markers")) fromTheMove += m.at("transmitter_position").get<int>() == 2;
  EXPECT_EQ(fromTheMove, shown["transmitter_positions"][1].at("points").get<int>());
  expectAllAcknowledgedStored(acknowledged(lines), shown);
  // In the board's frame (the simulated board's origin is at (-150, -150, -5) of the file's
  // frame, its axes the file's), every marker is the file's.
  ASSERT_EQ(leafdig("sessions export 1 --format markers --out " + quote(dir_) + " --db " + quote(db)).exitCode, 0);
  EXPECT_LT(worstMarkerOffTheBoardFileMm(dir_ / "session-1.markers.json", file), 1.5)
      << "a marker is off the file after the move";
  // The leaf's area interval is drawn with the fit's residual added to the digitizer's noise
  // (its points stand in two frames related by the fit), and still holds the area.
  ASSERT_EQ(leafdig("sessions export 1 --format model --out " + quote(dir_) + " --db " + quote(db)).exitCode, 0);
  const json modelFile = json::parse(slurp(dir_ / "session-1.model.json"));
  const json& metrics = modelFile.at("metrics");
  // The model file says which points came from which transmitter position, and each fit.
  ASSERT_EQ(modelFile.at("transmitter_positions").size(), 2u) << modelFile.dump();
  const json& second = modelFile["transmitter_positions"][1];
  EXPECT_EQ(second.at("rms_mm"), shown["transmitter_positions"][1].at("rms_mm"));
  EXPECT_EQ(second.at("items").size(), static_cast<std::size_t>(fromTheMove));
  EXPECT_EQ(modelFile["transmitter_positions"][0].at("items").size() + second.at("items").size(), 74u)
      << "the board's three points, the tip and the 70 markers, each once";
  for (const json& i : second.at("items")) EXPECT_EQ(i.at("what"), "marker") << i;
  EXPECT_NEAR(metrics.at("area_interval").at("digitizer_sigma_mm").get<double>(),
              std::hypot(0.762, shown["transmitter_positions"][1].at("rms_mm").get<double>()), 1e-9);
  EXPECT_LT(metrics["blade_area_95_mm2"][0].get<double>(), metrics["blade_area_mm2"].get<double>());
  EXPECT_GT(metrics["blade_area_95_mm2"][1].get<double>(), metrics["blade_area_mm2"].get<double>());
  // A curator corrects board point 2 as taken again (0.8 mm higher): the move is fitted again
  // and every marker pressed from the moved position is placed again; the others stay.
  json again;
  for (const json& b : shown.at("board_again"))
    if (b.at("col") == 2) again = b.at("position_mm");
  ASSERT_TRUE(again.is_array());
  const Result corrected = leafdig(
      "sessions correct 1 --what board_again --row 1 --col 2 --position " + std::to_string(again[0].get<double>()) +
      "," + std::to_string(again[1].get<double>()) + "," + std::to_string(again[2].get<double>() + 0.8) +
      " --who carla --why 'pressed on a crumb' --db " + quote(db));
  ASSERT_EQ(corrected.exitCode, 0) << corrected.err;
  const json after = show(db, 1);
  EXPECT_TRUE(after.at("chain_ok").get<bool>()) << after.at("problem");
  std::map<std::pair<int, int>, json> was;
  for (const json& m : shown.at("markers")) was[{m.at("row").get<int>(), m.at("col").get<int>()}] = m;
  int placedAgain = 0;
  for (const json& m : after.at("markers")) {
    const json& old = was.at({m.at("row").get<int>(), m.at("col").get<int>()});
    const double apart = std::hypot(m["position_mm"][0].get<double>() - old["position_mm"][0].get<double>(),
                                    m["position_mm"][1].get<double>() - old["position_mm"][1].get<double>(),
                                    m["position_mm"][2].get<double>() - old["position_mm"][2].get<double>());
    if (old.at("transmitter_position") == 2) {
      EXPECT_GT(apart, 1e-3) << m.dump();
      ++placedAgain;
    } else {
      EXPECT_EQ(apart, 0.0) << m.dump();
    }
  }
  EXPECT_EQ(placedAgain, fromTheMove);
  EXPECT_EQ(after.at("markers").size(), 70u);
  // One the move cannot fit (30 mm off) is refused by name, and nothing is written.
  const Result broken =
      leafdig("sessions correct 1 --what board_again --row 1 --col 2 --position " +
              std::to_string(again[0].get<double>() + 30) + "," + std::to_string(again[1].get<double>()) + "," +
              std::to_string(again[2].get<double>()) + " --who carla --why test --confirm --db " + quote(db));
  EXPECT_EQ(broken.exitCode, 2);
  EXPECT_NE(broken.err.find("move 1 no longer fits"), std::string::npos) << broken.err;
  EXPECT_EQ(show(db, 1).at("events"), after.at("events"));
  // A marker pressed after the move, corrected 1 mm where sessions show gives it: a 1 mm move,
  // within the unconfirmed limit (issue 49) — the point is held in the first frame already.
  json late;
  for (const json& m : after.at("markers"))
    if (m.at("transmitter_position") == 2) late = m;
  ASSERT_TRUE(late.is_object());
  const json& lp = late.at("position_mm");
  const Result nudged =
      leafdig("sessions correct 1 --what marker --row " + std::to_string(late.at("row").get<int>()) + " --col " +
              std::to_string(late.at("col").get<int>()) + " --position " + std::to_string(lp[0].get<double>()) + "," +
              std::to_string(lp[1].get<double>()) + "," + std::to_string(lp[2].get<double>() + 1.0) +
              " --who carla --why nudged --db " + quote(db));
  ASSERT_EQ(nudged.exitCode, 0) << nudged.err;
  EXPECT_NE(nudged.out.find(", moved 1.0 mm"), std::string::npos) << nudged.out;
  // Only a simulation moves the transmitter by itself; with devices the technician types 'move'.
  const Result alone = leafdig(
      "capture --relocate-source-after 5 --digitizer fastrak:/dev/null --caliper "
      "sylvac:/dev/null --db " +
      quote(dir_ / "other.sqlite") + " </dev/null");
  EXPECT_EQ(alone.exitCode, 2);
  EXPECT_NE(alone.err.find("goes with --simulate"), std::string::npos) << alone.err;
  EXPECT_FALSE(fs::exists(dir_ / "other.sqlite"));
  // The tolerance of a move's fit is set when a capture begins, within 0.1–10 mm; it is kept
  // in the session's settings.
  const Result tolerance =
      leafdig("capture --simulate --relocation-tolerance 20 --db " + quote(dir_ / "other.sqlite") + " </dev/null");
  EXPECT_EQ(tolerance.exitCode, 2);
  EXPECT_NE(tolerance.err.find("--relocation-tolerance must be a residual in mm, 0.1 to 10"), std::string::npos)
      << tolerance.err;
  EXPECT_FALSE(fs::exists(dir_ / "other.sqlite"));
  const Result kept = leafdig("capture --simulate --speed 20 --seed 4 --relocation-tolerance 2.5 --db " +
                              quote(dir_ / "kept.sqlite") + " --markers " + quote(file) + " </dev/null");
  ASSERT_EQ(kept.exitCode, 0) << kept.err;
  const Result settings =
      run("python3 -c \"import json, sqlite3, sys; c = sqlite3.connect('file:' + sys.argv[1] + '?mode=ro', "
          "uri=True); print(json.loads(c.execute('SELECT settings_json FROM sessions').fetchone()[0])['engine']"
          "['relocation_tolerance_mm'])\" " +
          quote(dir_ / "kept.sqlite"));
  ASSERT_EQ(settings.exitCode, 0) << settings.err;
  EXPECT_EQ(settings.out, "2.5\n");
}

// kill -9 across a move of the transmitter (issue 29): one capture is killed between the move
// and its fit (the station asks for the next board point again; the simulated transmitter's
// pose died with the process, so the virtual technician undoes the half-done move and goes on
// from the first position), another just after the fit (the resumed simulation stands where the
// fitted position stood). Both leaves come out as the file's; every acknowledged item is stored.
TEST_F(CaptureCli, ALeafKilledAcrossAMoveOfTheTransmitterResumesAndIsTheSameLeaf) {
  const std::string file = sample("lower-leaf-n10.markers.json");
  const auto relocation = [](const std::vector<json>& lines, const std::string& step) {
    return std::count_if(lines.begin(), lines.end(),
                         [&](const json& j) { return j.at("event") == "relocation" && j.at("step") == step; });
  };
  for (const std::string after : {"started", "fitted"}) {
    const fs::path db = dir_ / (after + ".sqlite"), out = dir_ / "out.jsonl", err = dir_ / "err.txt";
    const std::vector<json> killed = killWhen(
        {"capture", "--simulate", "--speed", "20", "--seed", "4", "--relocate-source-after", "10", "--json", "--db",
         db.string(), "--markers", file},
        [&](const std::vector<json>& lines) {
          // One board point again after the start; two more points after the fit.
          const auto at = std::find_if(lines.begin(), lines.end(), [&](const json& j) {
            return j.at("event") == "relocation" && j.at("step") == after;
          });
          return at != lines.end() && lines.end() - at > (after == "started" ? 1 : 2);
        },
        out, err);
    ASSERT_EQ(relocation(killed, after), 1) << after << ": " << slurp(err);
    if (after == "started") {
      ASSERT_EQ(relocation(killed, "fitted"), 0) << "killed before the fit";
    }
    const Result resumed = leafdig("sessions resume 1 --simulate --speed 20 --json --db " + quote(db) + " </dev/null");
    ASSERT_EQ(resumed.exitCode, 0) << after << ": " << resumed.err;
    const std::vector<json> more = jsonLines(resumed.out);
    if (after == "started") {
      EXPECT_EQ(relocation(more, "cancelled"), 1) << "the half-done move is undone";
    }
    const json shown = show(db, 1);
    EXPECT_EQ(shown.at("status"), "complete") << after;
    EXPECT_EQ(shown.contains("transmitter_positions"), after == "fitted") << after;
    std::map<std::int64_t, json> acks = acknowledged(killed);
    for (const auto& [seq, j] : acknowledged(more)) acks[seq] = j;
    expectAllAcknowledgedStored(acks, shown, db, 1);
    ASSERT_EQ(
        leafdig("sessions export 1 --format markers --out " + quote(dir_ / after) + " --db " + quote(db)).exitCode, 0);
    EXPECT_LT(worstMarkerOffTheBoardFileMm(dir_ / after / "session-1.markers.json", file), 1.5)
        << after << ": a marker is off the file";
  }
}

TEST_F(CaptureCli, FullModeInterleavedAndSmallModeCaptureTheirOwnReadings) {
  const fs::path db = dir_ / "station.sqlite";
  Result r = leafdig("capture --simulate --speed 12 --mode full --order interleaved --no-mistakes --json --db " +
                     quote(db) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  json shown = show(db, 1);
  EXPECT_EQ(shown.at("status"), "complete");
  EXPECT_EQ(shown.at("thickness").size(), 10u * 8);  // r_i4^1 and all 7 points per row, no d
  // Interleaved: row 1's readings come before row 2's markers.
  std::vector<std::string> order;
  for (const json& j : jsonLines(r.out))
    if (j.at("event") == "accepted")
      order.push_back(j.at("what").get<std::string>() +
                      std::to_string(j.at("row").is_null() ? 0 : j.at("row").get<int>()));
  const auto firstRow2 = std::find(order.begin(), order.end(), "marker2");
  const auto row1Reading = std::find(order.begin(), order.end(), "point_thickness1");
  EXPECT_LT(row1Reading - order.begin(), firstRow2 - order.begin());
  r = leafdig("capture --simulate --speed 12 --mode small --no-mistakes --json --db " + quote(db) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  shown = show(db, 2);
  EXPECT_EQ(shown.at("status"), "complete");
  EXPECT_EQ(shown.at("thickness").size(), 10u + 1);  // r_i4^1 per row and d
  EXPECT_EQ(
      leafdig("sessions export 2 --format markers,glb --out " + quote(dir_ / "x") + " --db " + quote(db)).exitCode, 0);
  EXPECT_EQ(leafdig("model build " + quote(dir_ / "x" / "session-2.markers.json")).exitCode, 0);
}

TEST_F(CaptureCli, CommandsOnStandardInputPauseAndAbandon) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("capture --simulate --speed 12 --json --db " + quote(db) + " < " +
                           quote(write("cmds.txt", "pause coffee\nfrobnicate\nabandon wrong leaf\n")));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("unknown command 'frobnicate'"), std::string::npos) << r.err;
  const auto lines = jsonLines(r.out);
  bool paused = false, abandoned = false;
  for (const json& j : lines) {
    paused = paused || (j.at("event") == "paused" && j.at("reason") == "coffee");
    abandoned = abandoned || j.at("event") == "abandoned";
  }
  EXPECT_TRUE(paused);
  EXPECT_TRUE(abandoned);
  EXPECT_EQ(show(db, 1).at("status"), "abandoned");
  const Result resume = leafdig("sessions resume 1 --simulate --db " + quote(db));
  EXPECT_EQ(resume.exitCode, 2);
  EXPECT_NE(resume.err.find("abandoned"), std::string::npos) << resume.err;
}

TEST_F(CaptureCli, AForeignOrCorruptDatabaseIsRefusedAndNotModified) {
  const fs::path text =
      write("notes.sqlite", std::string("this is a lab notebook, not a database\n") + std::string(5000, 'x'));
  const std::string before = slurp(text);
  const Result r = leafdig("capture --simulate --db " + quote(text));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("what to do"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(text), before);
  EXPECT_FALSE(fs::exists(dir_ / "notes.sqlite-wal"));
  // Another program's SQLite database.
  const fs::path other = dir_ / "other.sqlite";
  ASSERT_EQ(run("python3 -c \"import sqlite3; c=sqlite3.connect('" + other.string() +
                "'); c.execute('create table plants(x)'); c.commit()\"")
                .exitCode,
            0);
  const std::string otherBefore = slurp(other);
  const Result f = leafdig("sessions list --db " + quote(other));
  EXPECT_EQ(f.exitCode, 2);
  EXPECT_NE(f.err.find("not a leafdig one"), std::string::npos) << f.err;
  EXPECT_EQ(slurp(other), otherBefore);
  EXPECT_EQ(leafdig("sessions list --db " + quote(dir_ / "missing.sqlite")).exitCode, 2);
}

TEST_F(CaptureCli, BadDeviceSpecsAreRefusedBeforeAnythingIsWritten) {
  const fs::path db = dir_ / "s.sqlite";
  Result r = leafdig("capture --digitizer fastrak --caliper sylvac:/dev/null --db " + quote(db));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("needs a port"), std::string::npos) << r.err;
  r = leafdig("capture --digitizer wand:/dev/ttyS0 --caliper sylvac:/dev/ttyS1 --db " + quote(db));
  EXPECT_EQ(r.exitCode, 2);
  r = leafdig("capture --digitizer fastrak:/dev/ttyS0 --caliper hid:zz --db " + quote(db));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("VID:PID"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(db));
}

TEST_F(CaptureCli, TheDemoCapturesTheSampleAndSyntheticLeavesAndExportsThem) {
  const Result r = leafdig("demo --speed 15 --out " + quote(dir_ / "demo"));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("hash chain: OK"), std::string::npos);
  const json list = json::parse(leafdig("sessions list --json --db " + quote(dir_ / "demo" / "demo.sqlite")).out);
  ASSERT_EQ(list.size(), 6u);  // the three samples, two synthetic leaves, then the sample plant in place
  for (const auto& s : list) {
    EXPECT_EQ(s.at("status"), "complete");
    const std::string base = "session-" + std::to_string(s.at("id").get<int>());
    const bool plant = s.at("kind") == "plant";
    for (const char* ext : plant ? std::vector<const char*>{".mtg", ".plant.csv", ".plant-markers.json", ".survey.json"}
                                 : std::vector<const char*>{".glb", ".obj", ".ply", ".stl", ".model.json",
                                                            ".markers.json", ".markers.csv"})
      EXPECT_TRUE(fs::exists(dir_ / "demo" / (base + ext))) << base + ext;
  }
  EXPECT_EQ(list.back().at("kind"), "plant");
  EXPECT_NE(r.out.find("the sample plant where it stands (5 nodes) ... complete"), std::string::npos) << r.out;
  (void)leafdig::test::readMtgStrictly(
      slurp(dir_ / "demo" / ("session-" + std::to_string(list.back().at("id").get<int>()) + ".mtg")));
  // Each synthetic leaf's area against its exact area: printed, and close.
  int synthetic = 0;
  for (std::size_t at = r.out.find("against the exact "); at != std::string::npos;
       at = r.out.find("against the exact ", at + 1)) {
    const std::size_t colon = r.out.find(": ", at);
    const double percent = std::stod(r.out.substr(colon + 2));
    EXPECT_LT(std::abs(percent), 3.0) << r.out.substr(at, 60);
    ++synthetic;
  }
  EXPECT_EQ(synthetic, 2) << r.out;
  EXPECT_NE(r.out.find("against the leaf area meter's "), std::string::npos);
}

TEST_F(CaptureCli, ASyntheticLeafIsCapturedAndItsAreaComparedWithTheExactOne) {
  const fs::path db = dir_ / "s.sqlite";
  const Result r = leafdig(
      "capture --simulate --speed 12 --no-mistakes --seed 4 --stylus-noise 0.2 --synth "
      "shape=obovate,rows=6,length=300,serration=round,teeth=11 --db " +
      quote(db) + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const Result truth = leafdig(
      "synth leaf --shape obovate --rows 6 --length 300 --serration round --teeth 11 --json "
      "--markers " +
      quote(dir_ / "m.json") + " --truth " + quote(dir_ / "t.json"));
  ASSERT_EQ(truth.exitCode, 0) << truth.err;
  const double exact = json::parse(truth.out)["area_mm2"].get<double>();
  const Result e = leafdig("sessions export 1 --json --format markers --out " + quote(dir_) + " --db " + quote(db));
  ASSERT_EQ(e.exitCode, 0) << e.err;
  const json ac = json::parse(e.out)["metrics"]["area_constraint"];
  EXPECT_NEAR(ac["measured_mm2"].get<double>(), exact, 0.5);
  EXPECT_LT(std::abs(ac["difference_percent"].get<double>()), 3.0);
  const json markers = json::parse(slurp(dir_ / "session-1.markers.json"));
  EXPECT_EQ(markers["rows"].size(), 6u);
  // Refusals name the problem and write nothing.
  const fs::path other = dir_ / "o.sqlite";
  Result bad = leafdig("capture --simulate --synth shape=heart --db " + quote(other) + " </dev/null");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("heart"), std::string::npos) << bad.err;
  bad = leafdig("capture --simulate --synth shape=ovate,size=3 --db " + quote(other) + " </dev/null");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("unknown key 'size'"), std::string::npos) << bad.err;
  bad = leafdig("capture --simulate --synth shape=ovate --markers " + quote(sample("lower-leaf-n10.markers.json")) +
                " --db " + quote(other) + " </dev/null");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("not both"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(other));
}

}  // namespace
