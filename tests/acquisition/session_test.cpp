// Capture sessions on a real SQLite file: commit before acknowledge, replay on reopen,
// undo / retake / pause / abandon, the store refusing writes (page quota = full disk), a
// reader beside the writer, the board frame and the live preview.
#include "leafdig/acquisition/session/session.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "leafdig/acquisition/live/leaf_loop.hpp"
#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/leaf_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/preview.hpp"
#include "leafdig/model/leaf/markers_json.hpp"

namespace acq = leafdig::acquisition;
namespace fs = std::filesystem;
using FK = acq::Feedback::Kind;

namespace {

constexpr std::int64_t kMs = 1'000'000;

acq::Vec3 v(const Eigen::Vector3d& e) {
  return {e.x(), e.y(), e.z()};
}

// A technician's hand and caliper feeding a session.
struct Hand {
  acq::CaptureSession* session;
  std::int64_t t = 0;
  std::mt19937 rng{11};

  std::vector<acq::Feedback> press(const acq::Vec3& p, std::int64_t pressMs = 200) {
    std::normal_distribution<double> noise(0.0, 0.1);
    std::vector<acq::Feedback> out;
    const auto sample = [&](bool button) {
      acq::StylusInput s{
          t += 8 * kMs, {p[0] + noise(rng), p[1] + noise(rng), p[2] + noise(rng)}, button, "ok", "01   1.0  2.0  3.0",
          false};
      for (auto& f : session->onStylus(s)) out.push_back(f);
    };
    for (int i = 0; i < 60; ++i) sample(false);
    for (std::int64_t i = 0; i < pressMs / 8; ++i) sample(true);
    sample(false);
    return out;
  }
  std::vector<acq::Feedback> read(double mm) {
    return session->onCaliper({t += 500 * kMs, mm, "+" + std::to_string(mm)});
  }
};

bool has(const std::vector<acq::Feedback>& fs, FK k) {
  for (const auto& f : fs)
    if (f.kind == k) return true;
  return false;
}

// The projections read back from the events alone (db::project: how the lab server and an
// import see a session) are the ones the store kept as each event was written.
void expectProjectionFromEventsMatchesTheStore(const leafdig::db::Store& store, std::int64_t id) {
  const leafdig::db::Projected p = leafdig::db::project(store.events(id));
  const auto markers = store.markers(id);
  ASSERT_EQ(p.markers.size(), markers.size());
  for (std::size_t i = 0; i < markers.size(); ++i) {
    EXPECT_EQ(p.markers[i].seq, markers[i].seq);
    EXPECT_EQ(p.markers[i].what, markers[i].what);
    EXPECT_EQ(p.markers[i].row, markers[i].row);
    EXPECT_EQ(p.markers[i].col, markers[i].col);
    EXPECT_EQ(p.markers[i].positionMm, markers[i].positionMm);
  }
  const auto thickness = store.thickness(id);
  ASSERT_EQ(p.thickness.size(), thickness.size());
  for (std::size_t i = 0; i < thickness.size(); ++i) {
    EXPECT_EQ(p.thickness[i].seq, thickness[i].seq);
    EXPECT_EQ(p.thickness[i].what, thickness[i].what);
    EXPECT_EQ(p.thickness[i].valueMm, thickness[i].valueMm);
    EXPECT_EQ(p.thickness[i].raw, thickness[i].raw);
  }
  EXPECT_EQ(p.status.value_or("open"), store.session(id)->status);
}

class Session : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("leafdig-session-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    leaf_ =
        leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::int64_t create(leafdig::db::Store& store, acq::Settings settings = {}) {
    acq::SessionSetup s;
    s.project = "p";
    s.plant = "pl";
    s.settings = settings;
    s.digitizer = "fastrak:/dev/ttyS0";
    s.caliper = "sylvac:/dev/ttyS1";
    return acq::CaptureSession::create(store, s);
  }
  acq::Vec3 point(int row, int col) const {
    return v(leaf_.rows[static_cast<std::size_t>(row - 1)].pointsMm[static_cast<std::size_t>(col - 1)]);
  }
  // Tip and `rows` full rows.
  void captureRows(Hand& h, int rows) {
    ASSERT_TRUE(has(h.press(v(leaf_.tipMm)), FK::Accepted));
    for (int r = 1; r <= rows; ++r)
      for (int c = 1; c <= 7; ++c) ASSERT_TRUE(has(h.press(point(r, c)), FK::Accepted)) << r << "," << c;
  }
  void finish(Hand& h) {
    ASSERT_TRUE(has(h.press({500, 500, 500}, 1500), FK::RowsEnded));
    const int n = h.session->engine().completeRows();
    for (int r = 1; r <= n; ++r) {
      ASSERT_TRUE(has(h.read(*leaf_.rows[static_cast<std::size_t>(r - 1)].midribThicknessMm), FK::Accepted));
      ASSERT_TRUE(has(h.read(*leaf_.rows[static_cast<std::size_t>(r - 1)].veinOriginThicknessMm), FK::Accepted));
    }
    const auto last = h.read(*leaf_.edgeThicknessMm);
    ASSERT_TRUE(has(last, FK::Complete));
  }

  // A board frame's three points, and where the stylus reads a point of the first transmitter
  // position's frame once the transmitter was moved (half a radian about Z, and shifted).
  static constexpr acq::Vec3 kBoard[3] = {{-150, -150, -5}, {150, -150, -5}, {-150, 150, -5}};
  static acq::Vec3 from(const acq::Vec3& p) {
    Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
    moved.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    moved.translation() = Eigen::Vector3d(80, -40, 25);
    return v(moved * Eigen::Vector3d(p[0], p[1], p[2]));
  }

  fs::path dir_;
  leafdig::model::MarkerSet leaf_;
};

TEST_F(Session, EveryAcknowledgedItemIsInTheStoreAndReopeningReplaysTheExactState) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  {
    acq::CaptureSession s(store, id);
    Hand h{&s};
    captureRows(h, 4);
    // Each accepted feedback carries the seq of a stored event that says the same.
    const auto f = h.press(point(5, 1));
    ASSERT_EQ(f.size(), 1u);
    const auto events = store.events(id, f[0].seq);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, "accepted");
    EXPECT_EQ(store.markers(id).size(), 1u + 4 * 7 + 1);
  }
  acq::CaptureSession reopened(store, id);
  EXPECT_EQ(reopened.engine().step(), (acq::Step{acq::What::Marker, 5, 2}));
  EXPECT_EQ(reopened.engine().items().size(), 1u + 4 * 7 + 1);
  Hand h{&reopened};
  for (int r = 5; r <= 10; ++r)
    for (int c = r == 5 ? 2 : 1; c <= 7; ++c) ASSERT_TRUE(has(h.press(point(r, c)), FK::Accepted));
  finish(h);
  EXPECT_EQ(store.session(id)->status, "complete");
  EXPECT_TRUE(store.verify(id).ok);
  EXPECT_EQ(store.thickness(id).size(), 2u * 10 + 1);
  EXPECT_THROW(acq::CaptureSession(store, id), acq::SessionError);  // complete: not capturable
  // The complete leaf converts to a marker set equal (within the stylus noise) to the truth.
  const auto set = acq::toMarkerSet(reopened.engine().items(), reopened.engine().settings());
  ASSERT_EQ(set.rows.size(), 10u);
  EXPECT_LT((set.rows[9].pointsMm[3] - leaf_.rows[9].pointsMm[3]).norm(), 0.2);
  EXPECT_EQ(*set.edgeThicknessMm, *leaf_.edgeThicknessMm);
}

TEST_F(Session, UndoRetakeAndTheirCancellationSurviveReplayAndUpdateTheProjections) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  acq::CaptureSession s(store, id);
  Hand h{&s};
  captureRows(h, 2);
  // Undo by the very long press (no keyboard): the last marker leaves the projection.
  const auto before = store.markers(id).size();
  const auto undone = h.press(point(2, 7), 3200);
  ASSERT_TRUE(has(undone, FK::Undone));
  EXPECT_EQ(store.markers(id).size(), before - 1);
  ASSERT_TRUE(has(h.press(point(2, 7)), FK::Accepted));
  // Retake row 1 point 3: it becomes the step; the new point replaces the old one.
  const auto r = s.retake(acq::What::Marker, 1, 3);
  ASSERT_TRUE(has(r, FK::RetakeStarted));
  EXPECT_EQ(s.engine().step(), (acq::Step{acq::What::Marker, 1, 3}));
  EXPECT_NE(s.engine().prompt().find("Retake"), std::string::npos);
  acq::Vec3 moved = point(1, 3);
  moved[2] += 0.8;
  ASSERT_TRUE(has(h.press(moved), FK::Accepted));
  EXPECT_EQ(s.engine().step(), (acq::Step{acq::What::Marker, 3, 1}));
  // Retake the tip, then change one's mind: undo puts the old tip back.
  ASSERT_TRUE(has(s.retake(acq::What::Tip, 0, 0), FK::RetakeStarted));
  ASSERT_TRUE(has(s.undo(), FK::RetakeCancelled));
  EXPECT_FALSE(s.engine().retaking());
  // A retake of something never captured is refused, with words.
  const auto none = s.retake(acq::What::Marker, 7, 1);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].kind, FK::Rejected);
  EXPECT_NE(none[0].text.find("nothing was captured"), std::string::npos);

  acq::CaptureSession again(store, id);
  ASSERT_EQ(again.engine().items().size(), s.engine().items().size());
  for (const auto& item : s.engine().items()) {
    bool found = false;
    for (const auto& other : again.engine().items())
      found = found || (other.what == item.what && other.row == item.row && other.col == item.col &&
                        other.positionMm == item.positionMm);
    EXPECT_TRUE(found) << acq::toString(item.what) << " " << item.row << "," << item.col;
  }
  // The projection holds each current item exactly once, with the retaken position.
  const auto markers = store.markers(id);
  EXPECT_EQ(markers.size(), 1u + 14);
  int retaken = 0;
  for (const auto& m : markers)
    if (m.row == 1 && m.col == 3) {
      ++retaken;
      EXPECT_NEAR(m.positionMm[2], moved[2], 0.1);
    }
  EXPECT_EQ(retaken, 1);
  expectProjectionFromEventsMatchesTheStore(store, id);
}

TEST_F(Session, AFullStorePausesWithAClearMessageLosesNothingAndContinuesWhenSpaceReturns) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  acq::CaptureSession s(store, id);
  Hand h{&s};
  captureRows(h, 1);
  const auto acknowledged = store.markers(id).size();
  store.setMaxPages(store.pageCount());  // no room for one more page: "database or disk is full"
  // A few inserts may still fit in the last page; the first that does not pauses the
  // capture with the store's message.
  std::vector<acq::Feedback> f;
  for (int c = 1; c <= 7 && !s.paused(); ++c) f = h.press(point(2, c));
  ASSERT_TRUE(s.paused());
  ASSERT_FALSE(f.empty());
  EXPECT_EQ(f.back().kind, FK::Paused);
  EXPECT_EQ(f.back().seq, 0);  // nothing was written for it
  EXPECT_NE(f.back().text.find("full"), std::string::npos) << f.back().text;
  EXPECT_NE(s.snapshot(false).prompt.find("Paused"), std::string::npos);
  const auto step = s.engine().step();
  // While paused, the stylus changes nothing; a resume still fails while full.
  EXPECT_TRUE(h.press(point(2, step.col)).empty());
  (void)s.resume();
  EXPECT_TRUE(s.paused());
  // Space returns: capture goes on at the same step and nothing acknowledged is lost.
  store.setMaxPages(0);
  EXPECT_TRUE(has(s.resume(), FK::Resumed));
  EXPECT_FALSE(s.paused());
  EXPECT_EQ(s.engine().step(), step);
  for (int c = step.col; c <= 7; ++c) ASSERT_TRUE(has(h.press(point(2, c)), FK::Accepted));
  EXPECT_EQ(store.markers(id).size(), acknowledged + 7);
  EXPECT_TRUE(store.verify(id).ok);
  acq::CaptureSession reopened(store, id);
  EXPECT_EQ(reopened.engine().items().size(), s.engine().items().size());
}

TEST_F(Session, ACuratorReadsTheDatabaseWhileACaptureWritesAndNeitherBlocks) {
  const std::string path = (dir_ / "s.sqlite").string();
  leafdig::db::Store store(path);
  const auto id = create(store);
  std::atomic<bool> done{false};
  std::atomic<int> reads{0}, readerErrors{0};
  std::mutex seenMutex;
  std::set<std::size_t> seenCounts;  // marker counts the curator saw: the capture's progress
  std::thread curator([&] {
    leafdig::db::Store reader(path, true);
    while (!done) {
      try {
        (void)reader.sessions();
        const auto n = reader.markers(id).size();
        (void)reader.verify(id);
        {
          std::lock_guard lock(seenMutex);
          seenCounts.insert(n);
        }
        ++reads;
      } catch (const std::exception&) {
        ++readerErrors;
      }
    }
  });
  while (reads == 0) std::this_thread::yield();  // the curator is reading before the capture starts
  acq::CaptureSession s(store, id);
  Hand h{&s};
  ASSERT_TRUE(has(h.press(v(leaf_.tipMm)), FK::Accepted));
  for (int r = 1; r <= 10; ++r) {
    for (int c = 1; c <= 7; ++c) ASSERT_TRUE(has(h.press(point(r, c)), FK::Accepted)) << r << "," << c;
    // The curator gets a read in between rows; a reader blocked by the writer would not.
    const int before = reads;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (reads == before && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    ASSERT_GT(reads, before) << "the reader made no progress during row " << r;
  }
  EXPECT_FALSE(s.paused());  // a writer blocked by the reader would have paused
  const int readsDuringCapture = reads;
  done = true;
  curator.join();
  EXPECT_EQ(readerErrors, 0);
  EXPECT_GE(readsDuringCapture, 10);
  EXPECT_GE(seenCounts.size(), 5u) << "the curator should see the capture progress while it writes";
  EXPECT_EQ(store.markers(id).size(), 1u + 70);
}

TEST_F(Session, AnOperatorPauseSurvivesARestartAndAbandonEndsTheSession) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  {
    acq::CaptureSession s(store, id);
    Hand h{&s};
    captureRows(h, 1);
    ASSERT_TRUE(has(s.pause("lunch"), FK::Paused));
    EXPECT_TRUE(h.press(point(2, 1)).empty());  // ignored while paused
  }
  acq::CaptureSession s(store, id);
  EXPECT_TRUE(s.paused());
  EXPECT_NE(s.snapshot(false).prompt.find("lunch"), std::string::npos);
  ASSERT_TRUE(has(s.resume(), FK::Resumed));
  Hand h{&s};
  ASSERT_TRUE(has(h.press(point(2, 1)), FK::Accepted));
  ASSERT_TRUE(has(s.abandon("leaf torn"), FK::Abandoned));
  EXPECT_EQ(store.session(id)->status, "abandoned");
  EXPECT_THROW(acq::CaptureSession(store, id), acq::SessionError);
  EXPECT_TRUE(store.verify(id).ok);
}

TEST_F(Session, ABoardFrameIsCapturedFirstAndMarkersAreExpressedInIt) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  acq::Settings settings;
  settings.boardFrame = true;
  const auto id = create(store, settings);
  acq::CaptureSession s(store, id);
  Hand h{&s};
  EXPECT_EQ(s.engine().step(), (acq::Step{acq::What::Board, 0, 1}));
  // The board: origin at (100, 0, 0), +X along device +Y, +Y along device -X.
  ASSERT_TRUE(has(h.press({100, 0, 0}), FK::Accepted));
  const auto tooClose = h.press({105, 0, 0});
  ASSERT_FALSE(tooClose.empty());
  EXPECT_EQ(tooClose[0].kind, FK::Rejected);
  ASSERT_TRUE(has(h.press({100, 200, 0}), FK::Accepted));
  ASSERT_TRUE(has(h.press({-50, 100, 0}), FK::Accepted));
  EXPECT_EQ(s.engine().step().what, acq::What::Tip);
  ASSERT_TRUE(has(h.press({100, 50, 10}), FK::Accepted));
  const Eigen::Isometry3d frame = acq::boardFrame(s.engine().items());
  const Eigen::Vector3d tip =
      frame * Eigen::Vector3d(s.engine().items().back().positionMm[0], s.engine().items().back().positionMm[1],
                              s.engine().items().back().positionMm[2]);
  EXPECT_NEAR(tip.x(), 50, 0.2);
  EXPECT_NEAR(tip.y(), 0, 0.2);
  EXPECT_NEAR(tip.z(), 10, 0.2);
}

// Issue 29: a move of the transmitter made durable. The session is dropped (as kill -9 drops
// it) between the move and the board points taken again, and between them: reopened, it asks
// for the next board point again; once fitted, every later point is in the first frame.
TEST_F(Session, AMoveOfTheTransmitterSurvivesARestartAtEveryStepAndItsEventsAreChecked) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  acq::Settings settings;
  settings.boardFrame = true;
  const auto id = create(store, settings);
  const auto& board = kBoard;
  std::int64_t t = 0;
  {
    acq::CaptureSession s(store, id);
    Hand h{&s};
    for (const acq::Vec3& b : board) ASSERT_TRUE(has(h.press(b), FK::Accepted));
    captureRows(h, 1);
    const auto started = s.moveTransmitter(h.t);
    ASSERT_EQ(started.size(), 1u);
    EXPECT_EQ(started[0].kind, FK::Relocation);
    EXPECT_EQ(started[0].text, "started");
    EXPECT_EQ(started[0].relocation, 1);
    t = h.t;
  }
  for (int c = 1; c <= 3; ++c) {
    acq::CaptureSession s(store, id);  // reopened: the move is still in progress
    EXPECT_EQ(s.engine().step(), (acq::Step{acq::What::BoardAgain, 1, c}));
    Hand h{&s, t};
    ASSERT_TRUE(has(h.press(from(board[c - 1])), FK::Accepted));
    t = h.t;
  }
  {
    acq::CaptureSession s(store, id);
    EXPECT_EQ(s.engine().step(), (acq::Step{acq::What::BoardAgain, 1, 0}));
    Hand h{&s, t};
    const auto fitted = h.press(from(board[2]), 1500);
    ASSERT_TRUE(has(fitted, FK::Relocation));
    EXPECT_LT(fitted.back().fitRmsMm, 0.3);
    for (int c = 1; c <= 7; ++c) ASSERT_TRUE(has(h.press(from(point(2, c))), FK::Accepted)) << c;
    finish(h);
  }
  const acq::ReviewedSession r = acq::openForReview(store, id);
  EXPECT_EQ(r.engine.transmitterPositions(), 2);
  for (int c = 1; c <= 7; ++c) {
    const acq::Item* i = acq::findItem(r.engine.items(), acq::What::Marker, 2, c);
    ASSERT_NE(i, nullptr);
    EXPECT_LT(acq::distanceMm(i->positionMm, point(2, c)), 0.3) << c;
    EXPECT_EQ(i->frame, 1);
  }
  expectProjectionFromEventsMatchesTheStore(store, id);
  // Events a doctored file could hold: a fit before any move, a move of another number, a step
  // that is not one.
  leafdig::db::Event e;
  e.seq = 2;
  e.kind = "relocation";
  for (const std::string payload : {R"({"relocation":1,"step":"fitted"})", R"({"relocation":2,"step":"started"})",
                                    R"({"relocation":1,"step":"moved"})", R"({"relocation":0,"step":"started"})"}) {
    e.payloadJson = payload;
    EXPECT_THROW((void)acq::CaptureSession::replay(settings, {e}), acq::SessionError) << payload;
  }
}

// A board point taken again slipped: the move's fit placed every later marker a little off. The
// curator corrects the reading; the move is fitted again and its markers placed again (each by a
// correction event, in one transaction), a marker the curator set by hand stays, and a
// correction that breaks the fit is refused with nothing written.
TEST_F(Session, ACorrectedBoardPointTakenAgainPlacesEveryPointOfItsMoveAgain) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  acq::Settings settings;
  settings.boardFrame = true;
  const auto id = create(store, settings);
  const auto& board = kBoard;
  acq::Vec3 slipped = from(board[1]);
  slipped[2] += 1.6;  // pressed on a crumb of soil
  {
    acq::CaptureSession s(store, id);
    Hand h{&s};
    for (const acq::Vec3& b : board) ASSERT_TRUE(has(h.press(b), FK::Accepted));
    captureRows(h, 1);
    ASSERT_EQ(s.moveTransmitter(h.t).size(), 1u);
    for (const acq::Vec3& b : {from(board[0]), slipped, from(board[2])}) ASSERT_TRUE(has(h.press(b), FK::Accepted));
    ASSERT_TRUE(has(h.press(from(board[2]), 1500), FK::Relocation));
    for (int c = 1; c <= 7; ++c) ASSERT_TRUE(has(h.press(from(point(2, c))), FK::Accepted)) << c;
    finish(h);
  }
  const auto worstOff = [&] {
    const acq::ReviewedSession r = acq::openForReview(store, id);
    double worst = 0;
    for (int c = 1; c <= 7; ++c) {
      const acq::Item* i = acq::findItem(r.engine.items(), acq::What::Marker, 2, c);
      if (c != 4) worst = std::max(worst, acq::distanceMm(i->positionMm, point(2, c)));
    }
    return worst;
  };
  const double before = worstOff();
  EXPECT_GT(before, 0.5);  // the slip shows in the markers the move placed

  acq::Correction c;
  c.who = "curator";
  c.reason = "marker 4 re-measured on the leaf";
  c.what = acq::What::Marker;
  c.row = 2;
  c.col = 4;
  c.positionMm = point(2, 4);
  (void)acq::correct(store, id, c);
  const std::size_t eventsBefore = store.events(id).size();

  c.what = acq::What::BoardAgain;
  c.row = 1;
  c.col = 2;
  c.reason = "board point 2 was pressed on a crumb";
  c.positionMm = from(board[1]);
  const std::int64_t head = acq::correct(store, id, c);
  const auto events = store.events(id);
  ASSERT_EQ(events.size(), eventsBefore + 7);  // the board point and the six markers it placed
  EXPECT_EQ(head, events.back().seq);
  for (std::size_t k = eventsBefore; k < events.size(); ++k) EXPECT_EQ(events[k].kind, "corrected");
  EXPECT_TRUE(store.verify(id).ok) << store.verify(id).problem;
  expectProjectionFromEventsMatchesTheStore(store, id);
  EXPECT_LT(worstOff(), 0.3) << "before the correction: " << before;
  const acq::ReviewedSession r = acq::openForReview(store, id);
  const acq::Item* byHand = acq::findItem(r.engine.items(), acq::What::Marker, 2, 4);
  EXPECT_EQ(byHand->positionMm, point(2, 4));  // set by hand, in the first frame: not moved
  EXPECT_EQ(byHand->frame, 0);
  EXPECT_LT(r.engine.fitOf(1).fitRmsMm, 0.3);
  for (const auto& m : store.markers(id))
    if (m.what == "marker" && m.row == 2) {
      const acq::Item* i = acq::findItem(r.engine.items(), acq::What::Marker, 2, *m.col);
      EXPECT_EQ(m.positionMm, i->positionMm) << *m.col;  // the projection is the replayed model
    }

  // Corrected again to where it now is: the move fits as it did, so its markers stay (no
  // corrections that change nothing); only the board point's own event is written.
  c.reason = "board point 2 confirmed";
  (void)acq::correct(store, id, c);
  EXPECT_EQ(store.events(id).size(), events.size() + 1);
  EXPECT_EQ(store.events(id).back().payloadJson.find("placed again"), std::string::npos);

  // A correction the move cannot fit is refused, and nothing is written.
  const std::size_t held = store.events(id).size();
  c.positionMm = acq::Vec3{from(board[1])[0] + 30, from(board[1])[1], from(board[1])[2]};
  try {
    (void)acq::correct(store, id, c);
    FAIL() << "a board point that breaks the move's fit was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("move 1 no longer fits"), std::string::npos) << e.what();
  }
  EXPECT_EQ(store.events(id).size(), held);
}

TEST_F(Session, ThePreviewGrowsMidribFirstThenLateralsPerRowThenTheBlade) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  acq::CaptureSession s(store, id);
  Hand h{&s};
  ASSERT_TRUE(has(h.press(v(leaf_.tipMm)), FK::Accepted));
  EXPECT_TRUE(s.snapshot().preview->model.veins.empty());
  for (int c = 1; c <= 4; ++c) ASSERT_TRUE(has(h.press(point(1, c)), FK::Accepted));
  auto p = s.snapshot().preview;
  ASSERT_EQ(p->model.veins.size(), 1u);  // tip and row 1's midrib point: two balls
  EXPECT_EQ(p->model.veins[0].name, "midrib");
  EXPECT_TRUE(p->provisionalThickness);
  EXPECT_FALSE(p->mesh.organs.empty());
  for (int c = 5; c <= 7; ++c) ASSERT_TRUE(has(h.press(point(1, c)), FK::Accepted));
  p = s.snapshot().preview;
  EXPECT_EQ(p->model.veins.size(), 4u);  // midrib, two half-laterals, contour
  EXPECT_TRUE(p->model.blade.controlNet.empty());
  for (int c = 1; c <= 7; ++c) ASSERT_TRUE(has(h.press(point(2, c)), FK::Accepted));
  p = s.snapshot().preview;
  EXPECT_EQ(p->model.veins.size(), 6u);
  EXPECT_FALSE(p->model.blade.controlNet.empty());
  bool blade = false;
  for (const auto& o : p->mesh.organs) blade = blade || o.name == "blade";
  EXPECT_TRUE(blade);
  EXPECT_TRUE(p->notes.empty());
}

TEST(SessionReplay, ATamperedOrOutOfPlaceEventIsNamed) {
  leafdig::db::Event e;
  e.seq = 4;
  e.kind = "undone";
  e.payloadJson = R"({"what":"marker","row":1,"col":1,"seq":3})";
  try {
    (void)acq::CaptureSession::replay({}, {e});
    FAIL() << "an undo of nothing must not replay";
  } catch (const acq::SessionError& err) {
    EXPECT_NE(std::string(err.what()).find("event 4"), std::string::npos) << err.what();
  }
  e.kind = "accepted";
  e.payloadJson = R"({"what":"petiole"})";
  EXPECT_THROW((void)acq::CaptureSession::replay({}, {e}), acq::SessionError);
}

}  // namespace

// ---- review: corrections, flags, step replay, approval, export ------------------------------

TEST_F(Session, ACuratorsCorrectionIsAnEventThatReplaysAndReplacesTheProjection) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  acq::SessionSetup setup;
  setup.project = "p";
  setup.plant = "pl";
  setup.leafType = "lower";
  setup.measuredAreaMm2 = 1.0e4;
  const auto id = acq::CaptureSession::create(store, setup);
  EXPECT_EQ(store.session(id)->leafType, "lower");
  EXPECT_EQ(store.session(id)->measuredAreaMm2, 1.0e4);
  {
    acq::CaptureSession s(store, id);
    Hand h{&s};
    captureRows(h, 4);
    finish(h);
  }
  // Open sessions are not corrected; a correction needs a reason and an existing item.
  acq::Correction c;
  c.what = acq::What::Marker;
  c.row = 2;
  c.col = 3;
  c.positionMm = acq::Vec3{1, 2, 3};
  c.who = "curator";
  EXPECT_THROW((void)acq::correct(store, id, c), std::invalid_argument);  // no reason
  c.reason = "stylus slipped on the vein";
  c.row = 9;
  EXPECT_THROW((void)acq::correct(store, id, c), std::invalid_argument);  // no row 9
  c.row = 2;
  c.valueMm = 1.0;
  EXPECT_THROW((void)acq::correct(store, id, c), std::invalid_argument);  // a marker takes a position only
  c.valueMm.reset();
  const auto before = store.markers(id).size();
  const auto seq = acq::correct(store, id, c);
  EXPECT_EQ(store.events(id, seq)[0].kind, "corrected");
  EXPECT_TRUE(store.verify(id).ok);
  EXPECT_EQ(store.markers(id).size(), before);
  int found = 0;
  for (const auto& m : store.markers(id))
    if (m.what == "marker" && m.row == 2 && m.col == 3) {
      ++found;
      EXPECT_EQ(m.seq, seq);
      EXPECT_EQ(m.positionMm, (std::array<double, 3>{1, 2, 3}));
    }
  EXPECT_EQ(found, 1);
  const auto r = acq::openForReview(store, id);
  const auto* item = acq::findItem(r.engine.items(), acq::What::Marker, 2, 3);
  ASSERT_NE(item, nullptr);
  EXPECT_EQ(item->positionMm, (acq::Vec3{1, 2, 3}));
  EXPECT_EQ(item->flag, "corrected: stylus slipped on the vein");
  EXPECT_TRUE(r.engine.complete());
  // The review lists it among the flags; a thickness correction outside the range is refused.
  bool listed = false;
  for (const auto& f : acq::reviewFlags(r.engine.items())) listed = listed || f.text.find("corrected") == 0;
  EXPECT_TRUE(listed);
  acq::Correction t;
  t.what = acq::What::MidribThickness;
  t.row = 1;
  t.col = 4;
  t.who = "curator";
  t.reason = "typed in inches";
  t.valueMm = 254.0;
  EXPECT_THROW((void)acq::correct(store, id, t), std::invalid_argument);
  t.valueMm = 2.54;
  (void)acq::correct(store, id, t);
  EXPECT_DOUBLE_EQ(
      acq::findItem(acq::openForReview(store, id).engine.items(), acq::What::MidribThickness, 1, 4)->valueMm, 2.54);
  // The effect a curator saw is the one written, worked out at the event it names; another
  // curator's write since then refuses the write (the store's "moved on"), nothing written.
  t.valueMm = 2.6;
  const acq::CorrectionEffect seen = acq::previewCorrection(store, id, t);
  EXPECT_EQ(seen.head, store.session(id)->headSeq);
  EXPECT_EQ(seen.events, 1);
  acq::Correction other = t;
  other.who = "second curator";
  other.valueMm = 2.7;
  acq::CorrectionEffect written;
  const auto otherSeq = acq::correct(store, id, other, &written);
  EXPECT_EQ(written.head, seen.head);
  EXPECT_EQ(written.events, 1);
  t.seenHead = seen.head;
  try {
    (void)acq::correct(store, id, t);
    ADD_FAILURE() << "a correction confirmed before another curator's write was written";
  } catch (const leafdig::db::StoreError& e) {
    EXPECT_EQ(e.kind(), leafdig::db::StoreErrorKind::Conflict);
    EXPECT_NE(std::string(e.what()).find("moved on"), std::string::npos) << e.what();
  }
  EXPECT_EQ(store.session(id)->headSeq, otherSeq);
  EXPECT_DOUBLE_EQ(
      acq::findItem(acq::openForReview(store, id).engine.items(), acq::What::MidribThickness, 1, 4)->valueMm, 2.7);
  t.seenHead.reset();
  t.valueMm = 2.54;
  (void)acq::correct(store, id, t);
  // Approved sessions are final.
  EXPECT_THROW((void)acq::review(store, id, "rejected", "curator", ""), std::invalid_argument);  // no reason
  (void)acq::review(store, id, "approved", "curator", "");
  EXPECT_EQ(store.session(id)->status, "approved");
  EXPECT_THROW((void)acq::correct(store, id, t), std::invalid_argument);
  EXPECT_THROW((void)acq::review(store, id, "rejected", "curator", "late"), std::invalid_argument);
  // Review still opens it and the export carries the correction and the area constraint.
  acq::ExportRequest req;
  req.outDir = (dir_ / "out").string();
  req.formats = {"markers", "model", "glb"};
  const auto result = acq::exportSession(store, id, req);
  ASSERT_EQ(result.written.size(), 3u);
  for (const auto& p : result.written) EXPECT_GT(fs::file_size(p), 100u) << p;
  ASSERT_TRUE(result.metrics.areaConstraint.has_value());
  req.formats = {"dxf"};
  EXPECT_THROW((void)acq::exportSession(store, id, req), std::invalid_argument);
  expectProjectionFromEventsMatchesTheStore(store, id);
}

TEST_F(Session, ACuratorsDecisionsTakenInFromAnotherCopyOfTheSessionReplayAndChangeTheProjections) {
  // The station's file, and a copy of it (the lab server's copy of the session, in
  // miniature) where a curator corrects and approves: the station takes those events in.
  const fs::path stationFile = dir_ / "station.sqlite";
  const fs::path serverFile = dir_ / "server.sqlite";
  std::int64_t id = 0;
  {
    leafdig::db::Store store(stationFile.string());
    id = create(store);
    acq::CaptureSession s(store, id);
    Hand h{&s};
    captureRows(h, 3);
    ASSERT_TRUE(has(h.press(point(3, 7), 3200), FK::Undone));  // an undo among the events
    ASSERT_TRUE(has(h.press(point(3, 7)), FK::Accepted));
    finish(h);
  }
  fs::copy_file(stationFile, serverFile);
  leafdig::db::Store station(stationFile.string());
  leafdig::db::Store server(serverFile.string());
  const auto head = station.session(id)->headSeq;
  acq::Correction c;
  c.what = acq::What::MidribThickness;
  c.row = 2;
  c.col = 4;
  c.valueMm = 1.75;
  c.who = "curator";
  c.reason = "the caliper slipped off the midrib";
  (void)acq::correct(server, id, c);
  (void)acq::review(server, id, "approved", "curator", "");
  const auto decisions = server.events(id, head + 1);
  ASSERT_EQ(decisions.size(), 2u);

  station.import(id, decisions);
  EXPECT_TRUE(station.verify(id).ok);
  EXPECT_EQ(station.session(id)->status, "approved");
  EXPECT_EQ(station.session(id)->headHash, server.session(id)->headHash);
  expectProjectionFromEventsMatchesTheStore(station, id);
  const auto thickness = station.thickness(id);
  const auto serverThickness = server.thickness(id);
  ASSERT_EQ(thickness.size(), serverThickness.size());
  for (std::size_t i = 0; i < thickness.size(); ++i) {
    EXPECT_EQ(thickness[i].seq, serverThickness[i].seq);
    EXPECT_EQ(thickness[i].valueMm, serverThickness[i].valueMm);
  }
  EXPECT_DOUBLE_EQ(
      acq::findItem(acq::openForReview(station, id).engine.items(), acq::What::MidribThickness, 2, 4)->valueMm, 1.75);

  // Taken in twice, or an event that does not follow: refused, naming it, nothing changed.
  const auto before = station.events(id).size();
  try {
    station.import(id, decisions);
    FAIL() << "taken in twice";
  } catch (const leafdig::db::StoreError& e) {
    EXPECT_EQ(e.kind(), leafdig::db::StoreErrorKind::Conflict);
    EXPECT_NE(std::string(e.what()).find("event " + std::to_string(head + 1)), std::string::npos) << e.what();
  }
  auto forged = server.events(id, server.session(id)->headSeq)[0];
  forged.seq += 1;
  forged.prevHash = station.session(id)->headHash;
  forged.payloadJson = R"({"status":"rejected","who":"mallory","why":""})";
  EXPECT_THROW(station.import(id, {forged}), leafdig::db::StoreError);  // its hash does not match
  EXPECT_EQ(station.events(id).size(), before);
  EXPECT_EQ(station.session(id)->status, "approved");
}

TEST_F(Session, StepByStepReplayShowsTheLeafAsItWasAfterEachEvent) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  {
    acq::CaptureSession s(store, id);
    Hand h{&s};
    captureRows(h, 3);
    finish(h);
  }
  const auto events = store.events(id);
  std::size_t previous = 0;
  int grew = 0;
  for (const auto& e : events) {
    const auto r = acq::openForReview(store, id, e.seq);
    EXPECT_EQ(r.replayedEvents, e.seq);
    EXPECT_EQ(r.totalEvents, static_cast<std::int64_t>(events.size()));
    const std::size_t n = r.engine.items().size();
    if (e.kind == "accepted") {
      EXPECT_EQ(n, previous + 1) << "event " << e.seq;
      ++grew;
    } else {
      EXPECT_LE(n, previous + 1);
    }
    previous = n;
  }
  EXPECT_EQ(grew, 1 + 3 * 7 + 3 * 2 + 1);
  EXPECT_TRUE(acq::openForReview(store, id).engine.complete());
  EXPECT_THROW((void)acq::openForReview(store, id + 100), acq::SessionError);
}

TEST(ReviewFlags, ThicknessOutliersAndAMidribThickerThanBelowAreFlagged) {
  std::vector<acq::Item> items;
  for (int r = 1; r <= 8; ++r) {
    acq::Item m;
    m.what = acq::What::MidribThickness;
    m.row = r;
    m.valueMm = 0.8 + 0.1 * r;  // thicker towards the base: as it should be
    items.push_back(m);
  }
  EXPECT_TRUE(acq::reviewFlags(items).empty());
  items[2].valueMm = 6.0;  // row 3: a slip of the jaws
  const auto flags = acq::reviewFlags(items);
  ASSERT_GE(flags.size(), 2u);
  bool outlier = false, order = false;
  for (const auto& f : flags) {
    EXPECT_EQ(f.row, 3);
    outlier = outlier || f.text.find("MAD") != std::string::npos;
    order = order || f.text.find("nearer the base") != std::string::npos;
  }
  EXPECT_TRUE(outlier);
  EXPECT_TRUE(order);
}

TEST_F(Session, APedalHeldDownIsTheStylusButton) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  acq::CaptureSession session(store, id);
  std::mutex mutex;
  std::vector<FK> kinds;
  acq::LoopListener listener;
  listener.onFeedback = [&](const acq::Feedback& f) {
    std::lock_guard lock(mutex);
    kinds.push_back(f.kind);
  };
  acq::LeafCaptureLoop loop(session, listener, 1.0, acq::PreviewDetail::None);
  std::thread capture([&] { (void)loop.run(); });
  const auto t0 = leafdig::devices::Clock::now();
  int n = 0;
  const auto samples = [&](int count) {
    for (int i = 0; i < count; ++i) {
      leafdig::devices::StylusSample s;
      s.t = t0 + std::chrono::milliseconds(8 * n++);
      s.positionMm = v(leaf_.tipMm);
      s.button = false;  // the stylus button is never pressed: only the pedal
      loop.post(s);
    }
  };
  const auto accepted = [&] {
    std::lock_guard lock(mutex);
    return std::count(kinds.begin(), kinds.end(), FK::Accepted);
  };
  samples(60);
  EXPECT_FALSE(loop.pedal());
  loop.setPedal(true);
  EXPECT_TRUE(loop.pedal());
  samples(25);
  loop.setPedal(false);
  samples(5);
  for (int i = 0; i < 200 && accepted() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  loop.stop();
  capture.join();
  EXPECT_EQ(accepted(), 1);
  ASSERT_NE(acq::findItem(session.engine().items(), acq::What::Tip, 0, 0), nullptr);
  EXPECT_EQ(store.markers(id).size(), 1u);
}

// docs/schema.md: `raw` keeps a text record as the device sent it (CR LF included) and
// writes any other byte as \xNN, a backslash as \\ — so binary records stay valid text.
TEST_F(Session, RawDeviceRecordsAreStoredAsTextWithRealLineEndsAndEscapedBinary) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  acq::CaptureSession session(store, id);
  (void)session.pause("checking the raw column");
  acq::LeafCaptureLoop loop(session, acq::LoopListener{}, 1.0, acq::PreviewDetail::None);
  std::thread capture([&] { (void)loop.run(); });
  leafdig::devices::CaliperReading r;
  r.t = leafdig::devices::Clock::now();
  r.valueMm = 1.23;
  r.raw = std::string("+0001.23\r\n\x00\xff\\", 13);
  loop.post(r);
  for (int i = 0; i < 200 && store.events(id).back().kind != "ignored_reading"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  loop.stop();
  capture.join();
  const auto events = store.events(id);
  ASSERT_EQ(events.back().kind, "ignored_reading");  // paused: kept, but changes nothing
  EXPECT_EQ(events.back().raw, "+0001.23\r\n\\x00\\xff\\\\");
  EXPECT_TRUE(store.verify(id).ok);
}

// The station draws meshes of the preview; building them must never hold up the next decision
// (a technician answered late presses again). With a builder that blocks, every command is
// still answered, its snapshot carries the preview built so far (none yet), and once the
// builder is free the worker builds only the newest request, not every one it missed.
TEST_F(Session, ThePreviewWorkerNeverHoldsUpTheCaptureThreadAndBuildsOnlyTheNewest) {
  leafdig::db::Store store((dir_ / "s.sqlite").string());
  const auto id = create(store);
  acq::CaptureSession session(store, id);
  std::promise<void> release;
  const std::shared_future<void> released = release.get_future().share();
  std::atomic<int> builds{0};
  std::mutex mutex;
  std::vector<acq::Snapshot> snapshots;
  int feedback = 0;
  acq::LoopListener listener;
  listener.onFeedback = [&](const acq::Feedback&) {
    std::lock_guard lock(mutex);
    ++feedback;
  };
  listener.onSnapshot = [&](const acq::Snapshot& s) {
    std::lock_guard lock(mutex);
    snapshots.push_back(s);
  };
  const acq::PreviewBuilder builder = [&](const std::vector<acq::Item>& items, const acq::Settings& settings) {
    ++builds;
    released.wait();
    return acq::buildPreview(items, settings, {}, false);
  };
  acq::LeafCaptureLoop loop(session, listener, 1.0, acq::PreviewDetail::Meshes, builder);
  std::thread capture([&] { (void)loop.run(); });
  acq::Command pause = acq::parseCommand("pause checking the worker");
  acq::Command resume = acq::parseCommand("resume");
  for (int i = 0; i < 3; ++i) {
    loop.command(pause);
    loop.command(resume);
  }
  const auto answered = [&] {
    std::lock_guard lock(mutex);
    return feedback;
  };
  for (int i = 0; i < 1000 && answered() < 6; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::vector<acq::Snapshot> whileBlocked;
  {
    std::lock_guard lock(mutex);
    whileBlocked = snapshots;
  }
  const int answeredWhileBlocked = answered(), buildsWhileBlocked = builds.load();
  release.set_value();
  loop.stop();
  capture.join();
  ASSERT_EQ(answeredWhileBlocked, 6) << "the capture thread waited for the preview";
  ASSERT_EQ(whileBlocked.size(), 7u);  // the first, and one per answer
  for (const auto& s : whileBlocked) EXPECT_EQ(s.preview, nullptr);
  EXPECT_LE(buildsWhileBlocked, 1);
  EXPECT_LE(builds.load(), 2) << "the worker built requests that a newer one had replaced";
  std::lock_guard lock(mutex);
  ASSERT_GE(snapshots.size(), 8u);
  for (std::size_t i = 1; i < snapshots.size(); ++i) {
    EXPECT_GE(snapshots[i].version, snapshots[i - 1].version);
    EXPECT_GE(snapshots[i].previewVersion, snapshots[i - 1].previewVersion);
    EXPECT_LE(snapshots[i].previewVersion, snapshots[i].version);
  }
  const acq::Snapshot& last = snapshots.back();
  ASSERT_NE(last.preview, nullptr);
  EXPECT_EQ(last.previewVersion, last.version);
  EXPECT_EQ(last.version, session.snapshot(false).version);
}

// The capture loop is one for every kind of capture: a third kind is a LoopKind and nothing
// else (docs/architecture.md, "Adding a kind of capture"). A kind that only writes down what it
// is handed shows what the loop itself does: inputs in the order they were posted from another
// thread, the pedal pressing the stylus, one `device` per change of state, commands and releases
// counted once handed over, a refusing store retried until it takes, and quit ending the run.
namespace {
struct WritingDownKind {
  struct Command {
    int n = 0;  // 0: quit
  };
  using Result = std::vector<std::string>;
  struct Listen {};
  std::vector<std::string> told;
  std::atomic<bool> blocked{true};  // the store refuses until it is retried (the test's thread polls it)
  double timeScale() const { return 1.0; }
  void begin(Listen /*unused*/) { told.emplace_back("begin"); }
  void stylus(const acq::StylusInput& s) { told.push_back(s.button ? "pressed" : "up"); }
  void caliper(const acq::CaliperInput& c) { told.push_back("reading " + std::to_string(c.valueMm)); }
  bool command(const Command& c, std::int64_t /*now*/) {
    if (c.n == 0) return false;
    told.push_back("command " + std::to_string(c.n));
    return true;
  }
  void device(const std::string& device, const std::string& state, const std::string& /*message*/,
              std::int64_t /*now*/) {
    told.push_back(device + " " + state);
  }
  void retryStore(std::int64_t /*now*/) {
    blocked = false;
    told.emplace_back("retried");
  }
  bool storeBlocked() const { return blocked.load(); }
  bool ended() const { return false; }
  Result finish() {
    told.emplace_back("finish");
    return told;
  }
  WritingDownKind& session() { return *this; }
};
}  // namespace

TEST(CaptureLoop, AThirdKindOfCaptureIsOneLoopKindAndTheLoopDoesTheRest) {
  acq::CaptureLoop<WritingDownKind> loop;
  // Everything is posted before the run begins: the first batch has it all, in order.
  namespace dev = leafdig::devices;
  dev::StylusSample up;
  up.t = dev::Clock::now();
  loop.post(up);
  loop.setPedal(true);
  loop.post(up);  // pressed by the pedal
  loop.setPedal(false);
  loop.post(up);  // a release
  dev::DeviceStatus lost;
  lost.device = "FASTRAK";
  lost.state = dev::LinkState::Warning;
  loop.postStatus(lost);
  loop.postStatus(lost);  // the same state again: not a change
  dev::CaliperReading reading;
  reading.valueMm = 0.25;
  loop.post(reading);
  loop.command({7});
  std::vector<std::string> told;
  std::thread capture([&] { told = loop.run(); });
  for (int i = 0; i < 500 && (loop.commandsTaken() < 1 || loop.releasesTaken() < 1); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(loop.commandsTaken(), 1u);
  EXPECT_EQ(loop.releasesTaken(), 1u);
  // The store is retried a second after the run began (no sooner), whatever else arrives.
  for (int i = 0; i < 300 && loop.session().blocked; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  loop.command({0});
  capture.join();
  EXPECT_EQ(loop.commandsTaken(), 1u) << "quit ends the run; it is not counted";
  const std::vector<std::string> expected{
      "begin", "up", "pressed", "up", "FASTRAK warning", "reading 0.250000", "command 7", "retried", "finish"};
  EXPECT_EQ(told, expected);
}
