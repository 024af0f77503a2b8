// The station window's logic on Qt's offscreen platform: snapshots and feedback from a real
// capture session drive the banner, the step list, the device chips and the feedback line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <QApplication>
#include <QChart>
#include <QChartView>
#include <QFile>
#include <QSettings>
#include <QTest>
#include <QLabel>
#include <QListWidget>
#include <filesystem>
#include <functional>
#include <optional>

#include "leafdig/acquisition/session.hpp"
#include "leafdig/model/markers_json.hpp"
#include "export_dialog.hpp"
#include "leafdig/acquisition/review.hpp"
#include "review_view.hpp"
#include "settings_dialog.hpp"
#include "setup_dialog.hpp"
#include "station_window.hpp"

namespace acq = leafdig::acquisition;
namespace fs = std::filesystem;

namespace {

constexpr std::int64_t kMs = 1'000'000;

std::vector<acq::Feedback> press(acq::CaptureSession& s, std::int64_t& t, const Eigen::Vector3d& p) {
  std::vector<acq::Feedback> out;
  for (int i = 0; i < 70; ++i) {
    const bool button = i >= 40 && i < 65;
    for (auto& f : s.onStylus({t += 8 * kMs, {p.x(), p.y(), p.z()}, button, "ok", "01"})) out.push_back(f);
  }
  return out;
}

QStringList texts(const QListWidget* list) {
  QStringList out;
  for (int i = 0; i < list->count(); ++i) out << list->item(i)->text();
  return out;
}

TEST(StationWindow, TheBannerStepListAndFeedbackFollowTheSession) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-station-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  leafdig::db::Store store((dir / "s.sqlite").string());
  acq::SessionSetup setup;
  setup.project = "p";
  setup.plant = "pl";
  const auto id = acq::CaptureSession::create(store, setup);
  acq::CaptureSession session(store, id);
  const auto leaf = leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");

  leafdig::station::StationOptions options;
  options.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(options);
  EXPECT_TRUE(w.windowTitle().startsWith("leafdig"));
  w.applySnapshot(session.snapshot());
  EXPECT_EQ(w.bannerText().toStdString(), "Tip: touch the leaf tip and press");
  std::int64_t t = 0;
  ASSERT_EQ(press(session, t, leaf.tipMm).at(0).kind, acq::Feedback::Kind::Accepted);
  for (int c = 0; c < 7; ++c) ASSERT_EQ(press(session, t, leaf.rows[0].pointsMm[static_cast<std::size_t>(c)]).at(0).kind, acq::Feedback::Kind::Accepted);
  ASSERT_EQ(press(session, t, leaf.rows[1].pointsMm[0]).at(0).kind, acq::Feedback::Kind::Accepted);
  w.applySnapshot(session.snapshot());
  EXPECT_EQ(w.bannerText().toStdString(), "Row 2 · point 2 of 7 · right lateral vein");
  const auto* steps = w.findChild<QListWidget*>("steps");
  ASSERT_NE(steps, nullptr);
  const QStringList lines = texts(steps);
  EXPECT_TRUE(lines.contains("✓ Tip")) << lines.join(" | ").toStdString();
  EXPECT_TRUE(lines.contains("✓ Row 1 · 7 of 7 points")) << lines.join(" | ").toStdString();
  EXPECT_TRUE(lines.contains("▶ Row 2 · 1 of 7 points")) << lines.join(" | ").toStdString();
  // A rejection is shown with its reason; a device change gets a chip.
  acq::Feedback rejected;
  rejected.kind = acq::Feedback::Kind::Rejected;
  rejected.text = "the stylus moved 3.0 mm during the press";
  w.applyFeedback(rejected);
  bool shown = false;
  for (const auto* l : w.findChildren<QLabel*>()) shown = shown || l->text().contains("the stylus moved 3.0 mm");
  EXPECT_TRUE(shown);
  // Cues: an accept and a reject were asked for (sound or not, muted or not).
  EXPECT_EQ(w.sounds().requested(leafdig::station::Cue::Reject), 1);
  acq::Feedback accepted;
  accepted.kind = acq::Feedback::Kind::Accepted;
  accepted.item.what = acq::What::Marker;
  accepted.item.row = 2;
  accepted.item.col = 7;
  accepted.item.positionMm = {25.4, 0, 0};
  w.applyFeedback(accepted);
  EXPECT_EQ(w.sounds().requested(leafdig::station::Cue::StepDone), 1);  // a row's last point
  bool readout = false;
  for (const auto* l : w.findChildren<QLabel*>()) readout = readout || l->text().contains("x 25.4 mm");
  EXPECT_TRUE(readout);
  w.schematic()->resize(220, 320);
  // The schematic rings the next marker: row 2 point 2 lies right of the midrib (col 1 = right margin).
  const QPointF target = w.schematic()->targetPosition();
  ASSERT_FALSE(target.isNull());
  EXPECT_GT(target.x(), w.schematic()->width() / 2.0);
  // The preview holds the snapshot's partial model (midrib, row 1's laterals and contour).
  ASSERT_TRUE(w.lastSnapshot().has_value());
  EXPECT_EQ(w.lastSnapshot()->preview->model.veins.size(), 4u);
  fs::remove_all(dir);
}


fs::path freshDir(const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-station-" + tag + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A complete 3-row leaf in `store`, captured through a real session.
std::int64_t completeLeaf(leafdig::db::Store& store, std::optional<double> areaMm2 = {}) {
  const auto leaf = leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");
  acq::SessionSetup setup;
  setup.project = "p";
  setup.plant = "pl";
  setup.measuredAreaMm2 = areaMm2;
  const auto id = acq::CaptureSession::create(store, setup);
  acq::CaptureSession s(store, id);
  std::int64_t t = 0;
  (void)press(s, t, leaf.tipMm);
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t c = 0; c < 7; ++c) (void)press(s, t, leaf.rows[r].pointsMm[c]);
  (void)s.endRows(t);
  for (std::size_t r = 0; r < 3; ++r) {
    (void)s.onCaliper({t += 600 * kMs, *leaf.rows[r].midribThicknessMm, "m"});
    (void)s.onCaliper({t += 600 * kMs, *leaf.rows[r].veinOriginThicknessMm, "v"});
  }
  (void)s.onCaliper({t += 600 * kMs, *leaf.edgeThicknessMm, "d"});
  EXPECT_TRUE(s.engine().complete()) << s.engine().prompt();
  return id;
}

TEST(StationSettings, SaveLoadRoundTripsAndBadValuesAreNamedAndReplaced) {
  const fs::path dir = freshDir("settings");
  const QString file = QString::fromStdString((dir / "s.ini").string());
  leafdig::station::StationSettings s;
  s.units = "in";
  s.theme = "dark";
  s.fontScale = 1.6;
  s.shortcuts[leafdig::station::Action::Undo] = QKeySequence(Qt::Key_F5);
  s.engine.stillWindowNs = 400'000'000;
  s.save(file);
  QStringList problems;
  auto back = leafdig::station::StationSettings::load(file, &problems);
  EXPECT_TRUE(problems.isEmpty()) << problems.join("; ").toStdString();
  EXPECT_EQ(back.units, "in");
  EXPECT_EQ(back.theme, "dark");
  EXPECT_DOUBLE_EQ(back.fontScale, 1.6);
  EXPECT_EQ(back.shortcuts[leafdig::station::Action::Undo], QKeySequence(Qt::Key_F5));
  EXPECT_EQ(back.engine.stillWindowNs, 400'000'000);
  EXPECT_EQ(back.length(25.4, 2), "1.000 in");
  {
    QSettings q(file, QSettings::IniFormat);
    q.setValue("display/theme", "purple");
    q.setValue("display/font_scale", "huge");
    q.setValue("capture/still_window_ms", 99999);
  }
  back = leafdig::station::StationSettings::load(file, &problems);
  EXPECT_EQ(problems.size(), 3) << problems.join("; ").toStdString();
  EXPECT_EQ(back.theme, "light");
  EXPECT_DOUBLE_EQ(back.fontScale, leafdig::station::StationSettings().fontScale);
  // The dialog edits every field it shows.
  leafdig::station::SettingsDialog d(back);
  d.units()->setCurrentIndex(d.units()->findData("mm"));
  d.theme()->setCurrentIndex(d.theme()->findData("dark"));
  d.sounds()->setChecked(false);
  d.shortcut(leafdig::station::Action::Pause)->setKeySequence(QKeySequence(Qt::Key_F9));
  d.stillWindowMs()->setValue(300);
  const auto r = d.result();
  EXPECT_EQ(r.units, "mm");
  EXPECT_EQ(r.theme, "dark");
  EXPECT_FALSE(r.sounds);
  EXPECT_EQ(r.shortcuts.at(leafdig::station::Action::Pause), QKeySequence(Qt::Key_F9));
  EXPECT_EQ(r.engine.stillWindowNs, 300'000'000);
  fs::remove_all(dir);
}

TEST(Sounds, CuesArePreloadedWavFilesAndMuteSilencesThem) {
  leafdig::station::Sounds sounds;
  for (auto cue : {leafdig::station::Cue::Accept, leafdig::station::Cue::Reject, leafdig::station::Cue::StepDone,
                   leafdig::station::Cue::DeviceError}) {
    QFile f(sounds.file(cue));
    ASSERT_TRUE(f.open(QIODevice::ReadOnly)) << sounds.file(cue).toStdString();
    const QByteArray wav = f.readAll();
    EXPECT_TRUE(wav.startsWith("RIFF"));
    EXPECT_EQ(wav.mid(8, 8), QByteArray("WAVEfmt "));
    EXPECT_GT(wav.size(), 44 + 1000);
  }
  sounds.setMuted(true);
  sounds.play(leafdig::station::Cue::Reject);
  EXPECT_EQ(sounds.requested(leafdig::station::Cue::Reject), 1);
  EXPECT_EQ(sounds.played(leafdig::station::Cue::Reject), 0);
  // 0.1 s at 22050 Hz, 16-bit mono: 4410 bytes of samples after the 44-byte header.
  EXPECT_EQ(leafdig::station::synthesizeWav({{440, 0.1}}).size(), 44 + 4410);
}

TEST(SetupDialog, ChoicesComeFromTheRegistryAndBadEntriesAreNamed) {
  leafdig::devices::Inventory inv;
  leafdig::devices::SerialPortInfo port;
  port.path = "/dev/ttyUSB0";
  port.description = "USB serial";
  inv.serial.push_back(port);
  leafdig::devices::HidInfo hid;
  hid.vid = 0x0fe7;
  hid.pid = 0x4001;
  inv.hid.push_back(hid);
  const auto digitizers = leafdig::station::digitizerChoices(inv);
  const auto calipers = leafdig::station::caliperChoices(inv);
  const auto has = [](const auto& list, const QString& spec) {
    for (const auto& [label, s] : list)
      if (s == spec) return true;
    return false;
  };
  EXPECT_TRUE(has(digitizers, leafdig::station::kSimulatedDigitizer));
  EXPECT_TRUE(has(digitizers, "fastrak:/dev/ttyUSB0"));
  EXPECT_TRUE(has(calipers, "hid:0fe7:4001"));
  EXPECT_TRUE(has(calipers, "sylvac:/dev/ttyUSB0"));

  acq::SessionSetup defaults;
  defaults.project = "tobacco-2026";
  defaults.plant = "K326-7";
  defaults.simulated = true;
  leafdig::station::SetupDialog d(defaults, {}, inv);
  auto c = d.choice();
  ASSERT_TRUE(c.has_value());
  EXPECT_TRUE(c->setup.simulated);
  EXPECT_EQ(c->setup.project, "tobacco-2026");
  d.leafPosition()->setValue(5);
  d.leafType()->setText("upper");
  d.measuredArea()->setText("512.5");
  d.mode()->setCurrentText("full");
  d.order()->setCurrentText("interleaved");
  d.board()->setChecked(true);
  d.digitizer()->setCurrentIndex(d.digitizer()->findData("fastrak:/dev/ttyUSB0"));
  QString problem;
  EXPECT_FALSE(d.choice(&problem).has_value());  // a simulated caliper with a real digitizer
  EXPECT_TRUE(problem.contains("simulated")) << problem.toStdString();
  d.caliper()->setCurrentIndex(d.caliper()->findData("hid:0fe7:4001"));
  c = d.choice(&problem);
  ASSERT_TRUE(c.has_value()) << problem.toStdString();
  EXPECT_EQ(c->setup.leafPosition, 5);
  EXPECT_EQ(c->setup.leafType, "upper");
  EXPECT_DOUBLE_EQ(*c->setup.measuredAreaMm2, 51250.0);  // cm² → mm²
  EXPECT_EQ(c->setup.settings.mode, acq::Mode::Full);
  EXPECT_EQ(c->setup.settings.order, acq::Order::Interleaved);
  EXPECT_TRUE(c->setup.settings.boardFrame);
  EXPECT_EQ(c->setup.digitizer, "fastrak:/dev/ttyUSB0");
  d.caliper()->setEditText("caliper-on-com3");
  EXPECT_FALSE(d.choice(&problem).has_value());
  EXPECT_TRUE(problem.startsWith("Caliper:")) << problem.toStdString();
  d.caliper()->setCurrentIndex(d.caliper()->findData("hid:0fe7:4001"));
  d.project()->setEditText("  ");
  EXPECT_FALSE(d.choice(&problem).has_value());
  EXPECT_TRUE(problem.contains("project"));
}

TEST(ReviewView, ACuratorBrowsesSelectsCorrectsReplaysAndApproves) {
  const fs::path dir = freshDir("review");
  const std::string db = (dir / "s.sqlite").string();
  std::int64_t id = 0, open = 0;
  {
    leafdig::db::Store store(db);
    id = completeLeaf(store, 40000.0);
    acq::SessionSetup other;
    other.project = "q";
    other.plant = "x";
    open = acq::CaptureSession::create(store, other);
  }
  leafdig::station::ReviewView v(leafdig::station::StationSettings{});
  v.resize(1400, 900);
  v.setDatabase(db);
  EXPECT_EQ(v.sessionsTable()->rowCount(), 2);
  v.statusFilter()->setCurrentText("complete");
  ASSERT_EQ(v.sessionsTable()->rowCount(), 1);
  EXPECT_EQ(v.sessionsTable()->item(0, 0)->text().toLongLong(), id);
  ASSERT_TRUE(v.openSession(id));
  EXPECT_TRUE(v.bannerText().contains("chain OK")) << v.bannerText().toStdString();
  EXPECT_EQ(v.markersTable()->rowCount(), 1 + 21 + 6 + 1);
  EXPECT_TRUE(v.metricsText().contains("Blade area")) << v.metricsText().toStdString();
  EXPECT_TRUE(v.metricsText().contains("Measured area")) << v.metricsText().toStdString();
  ASSERT_NE(v.chart()->chart(), nullptr);
  EXPECT_GE(v.chart()->chart()->series().size(), 2);  // midrib + vein origin (+ flagged)
  // Table → 3D: selecting a row highlights that marker; 3D → table: a click picks it back.
  v.markersTable()->selectRow(9);  // row 2, point 2
  ASSERT_TRUE(v.preview()->highlight().has_value());
  const acq::Item picked = *v.preview()->highlight();
  EXPECT_EQ(picked.what, acq::What::Marker);
  EXPECT_EQ(picked.row, 2);
  EXPECT_EQ(picked.col, 2);
  v.preview()->resize(640, 480);
  const QPointF at = v.preview()->project(picked.positionMm);
  const auto hit = v.preview()->itemAt(at, 1.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->row, 2);
  EXPECT_EQ(hit->col, 2);
  v.markersTable()->clearSelection();
  v.selectItem(*hit);
  ASSERT_EQ(v.markersTable()->selectionModel()->selectedRows().size(), 1);
  EXPECT_EQ(v.markersTable()->selectionModel()->selectedRows()[0].row(), 9);
  // A correction with a reason becomes an event; without one it is refused and said.
  acq::Correction c;
  c.what = acq::What::VeinOriginThickness;
  c.row = 2;
  c.col = 4;
  c.valueMm = 0.9;
  c.who = "curator";
  EXPECT_FALSE(v.correct(c).isEmpty());
  EXPECT_TRUE(v.bannerText().contains("reason")) << v.bannerText().toStdString();
  c.reason = "caliper jaws on the vein, not beside it";
  EXPECT_TRUE(v.correct(c).isEmpty());
  bool flagged = false;
  for (int r = 0; r < v.markersTable()->rowCount(); ++r)
    flagged = flagged || v.markersTable()->item(r, 5)->text().startsWith("corrected: caliper jaws");
  EXPECT_TRUE(flagged);
  EXPECT_GE(v.flagsList()->count(), 1);
  // Step-by-step replay through the same engine.
  v.replayTo(5);
  EXPECT_TRUE(v.bannerText().contains("replay at event 5")) << v.bannerText().toStdString();
  EXPECT_LT(v.markersTable()->rowCount(), 6);
  v.replaySlider()->setValue(v.replaySlider()->maximum());
  EXPECT_EQ(v.markersTable()->rowCount(), 1 + 21 + 6 + 1);
  // Approve needs a name; then the session is approved and final.
  EXPECT_FALSE(v.approve("").isEmpty());
  EXPECT_TRUE(v.approve("curator").isEmpty());
  EXPECT_TRUE(v.bannerText().contains("approved")) << v.bannerText().toStdString();
  EXPECT_FALSE(v.reject("curator", "late").isEmpty());
  EXPECT_FALSE(v.openSession(open + 50));
  EXPECT_TRUE(v.bannerText().contains("no session")) << v.bannerText().toStdString();
  fs::remove_all(dir);
}

TEST(ExportBatch, ExportsEachSessionReportsTheOnesThatCannotAndCancels) {
  const fs::path dir = freshDir("export");
  const std::string db = (dir / "s.sqlite").string();
  std::int64_t done = 0, unfinished = 0;
  {
    leafdig::db::Store store(db);
    done = completeLeaf(store);
    acq::SessionSetup other;
    other.project = "q";
    other.plant = "x";
    unfinished = acq::CaptureSession::create(store, other);
  }
  acq::ExportRequest r;
  r.formats = {"glb", "csv"};
  r.outDir = (dir / "out").string();
  int calls = 0;
  const auto result = leafdig::station::exportBatch(db, {done, unfinished}, r, [&](int, int total, const QString&) {
    ++calls;
    EXPECT_EQ(total, 2);
    return true;
  });
  EXPECT_FALSE(result.cancelled);
  EXPECT_EQ(result.written.size(), 3u);  // glb + two CSVs
  ASSERT_EQ(result.failed.size(), 1u);
  EXPECT_EQ(result.failed[0].first, unfinished);
  EXPECT_EQ(calls, 3);
  for (const auto& p : result.written) EXPECT_TRUE(fs::exists(p)) << p;
  fs::remove_all(dir / "out");
  const auto cancelled = leafdig::station::exportBatch(db, {done, unfinished}, r, [](int, int, const QString&) { return false; });
  EXPECT_TRUE(cancelled.cancelled);
  EXPECT_TRUE(cancelled.written.empty());
  EXPECT_FALSE(fs::exists(dir / "out"));
  // The dialog turns its widgets into the request.
  leafdig::station::StationSettings settings;
  leafdig::station::ExportDialog d(settings);
  d.destination()->setText(QString::fromStdString(r.outDir));
  for (const auto& f : acq::exportFormats()) d.format(f)->setChecked(f == "obj");
  d.frame()->setCurrentIndex(d.frame()->findData("digitizer"));
  const auto req = d.request();
  EXPECT_EQ(req.formats, std::vector<std::string>{"obj"});
  EXPECT_EQ(req.frame, "digitizer");
  EXPECT_EQ(req.outDir, r.outDir);
  fs::remove_all(dir);
}

TEST(StationWindow, SimulatedDevicesShowRateAndAgeAndGoOffLineFromTheirChip) {
  const fs::path dir = freshDir("devices");
  leafdig::station::StationOptions o;
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.speed = 2;
  o.setup.project = "p";
  o.setup.plant = "pl";
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(o);
  ASSERT_TRUE(w.start()) << w.bannerText().toStdString();
  using Role = acq::DeviceSet::Role;
  const auto waitFor = [&](const std::function<bool()>& ok) {
    for (int i = 0; i < 300 && !ok(); ++i) QTest::qWait(20);
    return ok();
  };
  EXPECT_TRUE(waitFor([&] { return w.chipText(Role::Digitizer).contains("Hz"); })) << w.chipText(Role::Digitizer).toStdString();
  EXPECT_TRUE(w.chipText(Role::Digitizer).contains("streaming"));
  EXPECT_TRUE(w.chipText(Role::Digitizer).contains("s ago"));
  EXPECT_TRUE(waitFor([&] { return w.lastSnapshot().has_value(); }));
  // Each device (FASTRAK 8N1, the simulated Sylvac 4800 7E2) goes off-line from its chip and
  // comes back on the same port.
  for (const Role role : {Role::Digitizer, Role::Caliper}) {
    const auto chip = [&] { return w.chipText(role).toStdString(); };
    EXPECT_TRUE(waitFor([&] { return w.chipText(role).contains("streaming"); })) << chip();
    w.devices()->disconnect(role);
    w.refreshDevices();
    EXPECT_TRUE(w.chipText(role).contains("disconnected")) << chip();
    EXPECT_TRUE(w.chipText(role).contains("connect it again")) << chip();
    w.devices()->connect(role);
    EXPECT_TRUE(waitFor([&] { return w.chipText(role).contains("streaming"); })) << chip();
    EXPECT_FALSE(w.chipText(role).contains("cannot")) << chip();
  }
  // The Accept key held down is the stylus button (a foot pedal types it): press → down.
  QTest::keyPress(&w, Qt::Key_Return);
  EXPECT_TRUE(w.run()->pedal());
  QTest::keyRelease(&w, Qt::Key_Return);
  EXPECT_FALSE(w.run()->pedal());
  QWidget dialog;  // a dialog's Enter is not the pedal
  QTest::keyPress(&dialog, Qt::Key_Return);
  EXPECT_FALSE(w.run()->pedal());
  QTest::keyRelease(&dialog, Qt::Key_Return);
  // The session is open on this station: a restart offers to resume it.
  w.stopCapture();
  const auto open = w.interruptedSessions();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].id, w.sessionId());
  fs::remove_all(dir);
}

}  // namespace

int main(int argc, char** argv) {
  // Widget tests need no display (also when CTest lists the tests at build time).
  if (!qEnvironmentVariableIsSet("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  QApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
