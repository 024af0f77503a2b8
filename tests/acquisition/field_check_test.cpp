// The jig check as a technician drives it (issue 50): divots taken in order, a wrong divot refused
// by name — unless pressed again, a field may bend that far — a long press taking the last one
// back; and a stored check trusted only when its numbers are its presses': a record edited with
// sqlite3, its chain hash recomputed as an insider would, is refused by name.
#include "leafdig/acquisition/field/field_check.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/model/errors.hpp"

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
namespace fs = std::filesystem;

namespace {

m::Jig jig() {
  m::Jig j{"cube", {}};
  int k = 0;
  for (double z : {0.0, 100.0})
    for (double y : {0.0, 200.0})
      for (double x : {0.0, 300.0}) j.points.push_back({"D" + std::to_string(++k), Eigen::Vector3d(x, y, z)});
  return j;
}

// A press at `at`: still samples for half a second, the button down for 0.3 s, then up.
class Hand {
 public:
  acq::JigCapture::Decision press(acq::JigCapture& c, const Eigen::Vector3d& at, double heldS = 0.3) {
    acq::JigCapture::Decision last;
    const auto sample = [&](bool button) {
      acq::StylusInput s;
      s.tNs = t_;
      s.positionMm = {at.x(), at.y(), at.z()};
      s.button = button;
      s.raw = "01 sample";
      t_ += 10'000'000;
      const auto d = c.onStylus(s);
      if (d.kind != acq::JigCapture::Decision::Kind::Ignored) last = d;
    };
    for (int i = 0; i < 50; ++i) sample(false);
    for (int i = 0; i < static_cast<int>(heldS * 100); ++i) sample(true);
    sample(false);
    t_ += 1'000'000'000;
    return last;
  }

 private:
  std::int64_t t_ = 1'000'000'000;
};

using Kind = acq::JigCapture::Decision::Kind;

}  // namespace

TEST(JigCapture, DivotsAreTakenInOrderAndAWrongOneIsRefusedByName) {
  const m::Jig j = jig();
  acq::JigCapture c(j);
  Hand hand;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  pose.pretranslate(Eigen::Vector3d(-200, -400, 20));
  EXPECT_EQ(c.prompt().substr(0, 26), "touch divot D1 (1 of 8) an");
  for (int i = 0; i < 3; ++i) EXPECT_EQ(hand.press(c, pose * j.points[i].pointMm).kind, Kind::Accepted);
  // D4 asked for; the technician touches D8 (100 mm above it).
  auto d = hand.press(c, pose * j.points[7].pointMm);
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.words.find("this is not divot D4: it is 100 mm from where D4 is on the jig (it is nearer D8)"),
            std::string::npos)
      << d.words;
  EXPECT_EQ(c.next(), 3U);
  // Touched again at the same place, it is taken: the technician is sure.
  d = hand.press(c, pose * j.points[7].pointMm);
  EXPECT_EQ(d.kind, Kind::Accepted) << d.words;
  // It was wrong after all: a long press takes it back.
  d = hand.press(c, Eigen::Vector3d(0, 0, 0), 3.2);
  EXPECT_EQ(d.kind, Kind::Undone);
  EXPECT_EQ(d.words, "D4 taken back");
  for (std::size_t i = 3; i < j.points.size(); ++i)
    EXPECT_EQ(hand.press(c, pose * j.points[i].pointMm).kind, Kind::Accepted) << i;
  EXPECT_TRUE(c.done());
  EXPECT_EQ(hand.press(c, pose * j.points[0].pointMm).kind, Kind::Rejected);
  std::vector<acq::Vec3> points;
  for (const auto& p : c.taken()) points.push_back(p.positionMm);
  const acq::FieldCheckResult r = acq::checkField(j, points, 1.5);
  EXPECT_LT(r.fit.rmsMm, 1e-6);
  EXPECT_EQ(r.verdict, "pass");
  acq::JigCapture empty(j);
  EXPECT_EQ(empty.undo().words, "no divot is taken yet: nothing to undo");
}

TEST(FieldCheckRecord, AStoredCheckIsTrustedOnlyWhenItsNumbersAreItsPresses) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-field-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "station.sqlite").string();
  const m::Jig j = jig();
  std::vector<acq::JigPress> presses;
  std::vector<acq::Vec3> points;
  for (const auto& p : j.points) {
    const Eigen::Vector3d at = p.pointMm + Eigen::Vector3d(0.002 * p.pointMm.x(), 0, -0.01 * p.pointMm.z());
    presses.push_back({{at.x(), at.y(), at.z()}, "01 " + p.id, 0});
    points.push_back(presses.back().positionMm);
  }
  const acq::FieldCheckResult r = acq::checkField(j, points, 0.2);
  ASSERT_NE(r.verdict, "pass");
  {
    leafdig::db::Store store(path);
    store.addFieldCheck({"bench", "ana", "fastrak", "/dev/ttyUSB0", r.verdict,
                         acq::encodeFieldCheck(j, presses, r, "fastrak:/dev/ttyUSB0")});
    const auto back = acq::fieldCalibrations(store);
    ASSERT_EQ(back.size(), 1U);
    EXPECT_EQ(back[0].result.verdict, r.verdict);
    EXPECT_EQ(back[0].result.fit.rmsMm, r.fit.rmsMm);
    EXPECT_EQ(back[0].presses[3].raw, "01 D4");
  }
  // An insider turns the verdict into a pass and the RMS into 0.1 mm, and recomputes the hash.
  leafdig::db::FieldCheckRow row;
  {
    leafdig::db::Store store(path);
    row = store.fieldChecks().at(0);
  }
  nlohmann::json doc = nlohmann::json::parse(row.recordJson);
  doc["rms_mm"] = 0.1;
  doc["verdict"] = "pass";
  row.recordJson = doc.dump();
  row.verdict = "pass";
  row.hash = leafdig::db::fieldCheckHash(row);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_exec(db, "DROP TRIGGER field_checks_no_update", nullptr, nullptr, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_prepare_v2(db, "UPDATE field_checks SET verdict=?1, record_json=?2, hash=?3 WHERE id=1", -1, &st,
                               nullptr),
            SQLITE_OK);
  sqlite3_bind_text(st, 1, row.verdict.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 2, row.recordJson.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(st, 3, row.hash.c_str(), -1, SQLITE_TRANSIENT);
  ASSERT_EQ(sqlite3_step(st), SQLITE_DONE);
  sqlite3_finalize(st);
  ASSERT_EQ(sqlite3_exec(db,
                         "CREATE TRIGGER field_checks_no_update BEFORE UPDATE ON field_checks\n"
                         "  BEGIN SELECT RAISE(ABORT, 'field checks are append-only: run a new check'); END",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  leafdig::db::Store store(path, true);
  ASSERT_EQ(store.fieldChecks().size(), 1U) << "the chain verifies: the insider recomputed it";
  try {
    (void)acq::fieldCalibrations(store);
    ADD_FAILURE() << "an edited check was trusted";
  } catch (const m::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field check 1: its verdict is not what its presses give (" + r.verdict + ")"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

TEST(FieldApplied, ACaptureSaysWhichCheckCorrectsItOrThatTheFieldWasNotCheckedToday) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-field-banner-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  leafdig::db::Store store((dir / "s.sqlite").string());
  EXPECT_EQ(acq::fieldBanner(store, std::nullopt),
            "field: not corrected, and no check of the field today (leafdig field check)");
  EXPECT_EQ(acq::fieldBanner(store, std::nullopt, 48),
            "field: not corrected, and no check of the field in the last 48 h (leafdig field check)");
  EXPECT_THROW((void)acq::resolveFieldCalibration(store, "latest"), std::invalid_argument);
  EXPECT_FALSE(acq::resolveFieldCalibration(store, "none"));
  EXPECT_THROW((void)acq::resolveFieldCalibration(store, "two"), std::invalid_argument);
  const m::Jig j = jig();
  std::vector<acq::JigPress> presses;
  std::vector<acq::Vec3> points;
  for (const auto& p : j.points) {
    const Eigen::Vector3d at = p.pointMm + Eigen::Vector3d(0.004 * p.pointMm.x(), 0, -0.02 * p.pointMm.z());
    presses.push_back({{at.x(), at.y(), at.z()}, "01", 0});
    points.push_back(presses.back().positionMm);
  }
  const acq::FieldCheckResult r = acq::checkField(j, points, 0.5);
  ASSERT_EQ(r.verdict, "correctable");
  store.addFieldCheck(
      {"bench", "ana", "fastrak", "/dev/ttyUSB0", r.verdict, acq::encodeFieldCheck(j, presses, r, "x")});
  EXPECT_NE(acq::fieldBanner(store, std::nullopt).find("field: not corrected (check 1, correctable, is 0 h old"),
            std::string::npos)
      << acq::fieldBanner(store, std::nullopt);
  const auto applied = acq::resolveFieldCalibration(store, "latest");
  ASSERT_TRUE(applied);
  EXPECT_EQ(applied->id, 1);
  EXPECT_EQ(applied->hash, store.fieldChecks().at(0).hash);
  EXPECT_EQ(acq::fieldBanner(store, applied).substr(0, 34), "field: corrected by field check 1 ");
  // Kept in a session's settings and read back the same; a bent value is refused by name.
  nlohmann::json settings = {{"field_calibration", acq::fieldAppliedJson(*applied)}};
  const auto back = acq::fieldAppliedFromSettings(settings.dump(), "session 9");
  ASSERT_TRUE(back);
  EXPECT_EQ(back->correction.name(), applied->correction.name());
  const acq::Vec3 p{100, 50, 80};
  EXPECT_EQ(back->apply(p), applied->apply(p));
  settings["field_calibration"]["verdict"] = "fail";
  EXPECT_THROW((void)acq::fieldAppliedFromSettings(settings.dump(), "session 9"), m::InputError);
  // A failed check is never applied.
  std::vector<acq::Vec3> far;
  std::vector<acq::JigPress> farPresses;
  for (const auto& q : points) {
    far.push_back({q[0], q[1], q[2] + 5 * std::sin(q[0] / 37.0) + 3 * std::cos(q[1] / 23.0)});
    farPresses.push_back({far.back(), "01", 0});
  }
  const acq::FieldCheckResult bad = acq::checkField(j, far, 0.01);
  ASSERT_EQ(bad.verdict, "fail");
  store.addFieldCheck(
      {"bench", "ana", "fastrak", "/dev/ttyUSB0", bad.verdict, acq::encodeFieldCheck(j, farPresses, bad, "x")});
  try {
    (void)acq::resolveFieldCalibration(store, "latest");
    ADD_FAILURE() << "a failed check was applied";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("field check 2 failed: the field is beyond correcting"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(acq::resolveFieldCalibration(store, "1")->id, 1);
  fs::remove_all(dir);
}

// The correction is the field around the transmitter where the check found it: a capture
// through it takes no move of the transmitter, leaf or plant, and says why (a `rejected` event
// that replays as nothing); without a check the engine answers the move as before.
TEST(FieldApplied, ACaptureThroughACheckedFieldRefusesAMoveOfTheTransmitterInWords) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-field-move-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  leafdig::db::Store store((dir / "s.sqlite").string());
  acq::FieldApplied field;
  field.id = 4;
  field.hash = std::string(64, 'a');
  field.createdUtc = "2026-11-29T06:00:00.000Z";
  field.verdict = "correctable";
  field.holdoutRmsMm = 0.4;
  acq::SessionSetup leaf;
  leaf.project = "p";
  leaf.plant = "plant-1";
  leaf.station = "bench";
  leaf.field = field;
  const std::int64_t corrected = acq::CaptureSession::create(store, leaf);
  leaf.field.reset();
  const std::int64_t plain = acq::CaptureSession::create(store, leaf);
  {
    acq::CaptureSession s(store, corrected);
    const auto f = s.moveTransmitter();
    ASSERT_EQ(f.size(), 1U);
    EXPECT_EQ(f[0].kind, acq::Feedback::Kind::Rejected);
    EXPECT_NE(f[0].text.find("the transmitter stays where field check 4 found the field"), std::string::npos)
        << f[0].text;
    EXPECT_GT(f[0].seq, 0);
    EXPECT_EQ(s.engine().relocating(), 0);
  }
  EXPECT_EQ(store.events(corrected).back().kind, "rejected");
  EXPECT_EQ(acq::CaptureSession(store, corrected).engine().relocating(), 0);  // replays as nothing
  {
    acq::CaptureSession s(store, plain);
    const auto f = s.moveTransmitter();
    ASSERT_FALSE(f.empty());  // the engine's own answer (before the board: its words), not the field's
    EXPECT_EQ(f[0].text.find("field check"), std::string::npos) << f[0].text;
  }
  acq::PlantSessionSetup plant;
  plant.project = "p";
  plant.plant = "plant-2";
  plant.station = "bench";
  plant.field = field;
  const std::int64_t plantId = acq::PlantCaptureSession::create(store, plant);
  acq::PlantCaptureSession s(store, plantId);
  const acq::PlantFeedback f = s.moveTransmitter();
  EXPECT_EQ(f.decision.kind, acq::PlantDecision::Kind::Rejected);
  EXPECT_NE(f.decision.reason.find("--field-calibration none"), std::string::npos) << f.decision.reason;
  EXPECT_EQ(s.engine().relocating(), 0);
  EXPECT_EQ(store.events(plantId).back().kind, "rejected");
  fs::remove_all(dir);
}

// Sentinel divots (issue 50): a few of the check's divots, spread over the jig, taken again before
// a capture; each compared with where the check found it; kept with the check in a session's
// settings and read back only when their numbers are their own and they held.
TEST(FieldSentinels, DivotsSpreadOverTheJigAreComparedWithTheCheckAndKeptOnlyWhenTheyHeld) {
  const m::Jig j = jig();
  // The cube's eight corners: four spread ones are never four of one face.
  const m::Jig four = acq::sentinelJig(j, 4);
  ASSERT_EQ(four.points.size(), 4U);
  double zs = 0, xs = 0, ys = 0;
  for (const auto& p : four.points) {
    zs += p.pointMm.z();
    xs += p.pointMm.x();
    ys += p.pointMm.y();
  }
  EXPECT_EQ(zs, 200.0) << "two on each level";
  EXPECT_EQ(xs, 600.0);
  EXPECT_EQ(ys, 400.0);
  for (std::size_t i = 1; i < four.points.size(); ++i)
    EXPECT_LT(std::stoi(four.points[i - 1].id.substr(1)), std::stoi(four.points[i].id.substr(1))) << "the jig's order";
  EXPECT_EQ(acq::sentinelJig(j, 4).points[0].id, four.points[0].id) << "the same choice every time";
  EXPECT_THROW((void)acq::sentinelJig(j, 2), std::invalid_argument);
  EXPECT_THROW((void)acq::sentinelJig(j, 6), std::invalid_argument);
  m::Jig small{"three", {j.points[0], j.points[3], j.points[5]}};
  EXPECT_EQ(acq::sentinelJig(small, 5).points.size(), 3U) << "at most the jig's divots";

  acq::FieldCalibration check;
  check.id = 7;
  check.jig = j;
  check.result.toleranceMm = 1.5;
  for (const auto& p : j.points) check.presses.push_back({{p.pointMm.x(), p.pointMm.y(), p.pointMm.z()}, "01", 0});
  // Taken again: the first three where they were (within noise), the last 2.5 mm higher.
  std::vector<acq::JigPress> again;
  for (std::size_t i = 0; i < four.points.size(); ++i) {
    const Eigen::Vector3d at = four.points[i].pointMm + Eigen::Vector3d(0.05, 0, i == 3 ? 2.5 : 0.0);
    again.push_back({{at.x(), at.y(), at.z()}, "01", 0});
  }
  const acq::FieldSentinels moved = acq::compareSentinels(check, four, again, "2026-11-30T06:00:00.000Z");
  EXPECT_NEAR(moved.divots[0].movedMm, 0.05, 1e-12);
  EXPECT_NEAR(moved.worst().movedMm, std::hypot(0.05, 2.5), 1e-12);
  EXPECT_EQ(moved.worst().id, four.points[3].id);
  EXPECT_TRUE(moved.moved());
  EXPECT_NE(moved.words().find("beyond its 1.50 mm: the field moved since the check"), std::string::npos)
      << moved.words();
  EXPECT_NE(moved.words().find("leafdig field check"), std::string::npos);
  again[3].positionMm[2] -= 2.5;
  const acq::FieldSentinels held = acq::compareSentinels(check, four, again, "2026-11-30T06:00:00.000Z");
  EXPECT_FALSE(held.moved());
  EXPECT_EQ(held.words(), "4 sentinel divots of field check 7 taken again: the largest move 0.05 mm (" +
                              held.worst().id + "), within its 1.50 mm");
  m::Jig stranger = four;
  stranger.points[0].id = "Z9";
  EXPECT_THROW((void)acq::compareSentinels(check, stranger, again, "t"), std::invalid_argument);

  // Kept with the check a session applies, and read back the same.
  std::optional<acq::FieldApplied> applied = acq::FieldApplied{};
  applied->id = 7;
  applied->hash = "h";
  applied->createdUtc = "2026-11-30T05:00:00.000Z";
  applied->verdict = "pass";
  EXPECT_THROW(acq::attachSentinels(applied, moved), std::invalid_argument) << "moved: no session";
  std::optional<acq::FieldApplied> none;
  EXPECT_THROW(acq::attachSentinels(none, held), std::invalid_argument) << "sentinels of no check applied";
  acq::attachSentinels(applied, held);
  nlohmann::json settings = {{"field_calibration", acq::fieldAppliedJson(*applied)}};
  EXPECT_EQ(settings["field_calibration"]["sentinels"]["verdict"], "held");
  const auto back = acq::fieldAppliedFromSettings(settings.dump(), "session 3");
  ASSERT_TRUE(back && back->sentinels);
  EXPECT_EQ(back->sentinels->words(), held.words());
  EXPECT_EQ(acq::sentinelsJson(*back->sentinels), acq::sentinelsJson(held));
  // Edited with sqlite3: a smaller move than the divots', a verdict of its own, a moved set, a key
  // leafdig does not read — each refused by name.
  const auto refused = [&](nlohmann::json edited, const std::string& words) {
    try {
      (void)acq::fieldAppliedFromSettings(edited.dump(), "session 3");
      ADD_FAILURE() << "taken: " << edited.dump();
    } catch (const m::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  nlohmann::json edited = settings;
  edited["field_calibration"]["sentinels"]["max_mm"] = 0.01;
  refused(edited, "session 3: field_calibration.sentinels: max_mm and worst_point are not the divots' own");
  edited = settings;
  edited["field_calibration"]["sentinels"]["verdict"] = "moved";
  refused(edited, "the verdict is not the divots' own");
  edited = settings;
  edited["field_calibration"]["sentinels"]["divots"][1]["moved_mm"] = 9.0;
  edited["field_calibration"]["sentinels"]["max_mm"] = 9.0;
  edited["field_calibration"]["sentinels"]["worst_point"] = held.divots[1].id;
  edited["field_calibration"]["sentinels"]["verdict"] = "moved";
  refused(edited, "a session does not begin through a moved field");
  edited = settings;
  edited["field_calibration"]["sentinels"]["note"] = "x";
  refused(edited, "has a key leafdig does not read: note");
  edited = settings;
  edited["field_calibration"]["sentinels"]["divots"][0]["position_mm"][2] = 1e300;
  refused(edited, "divots[0].position_mm is not three numbers");
}
