// The station window's logic on Qt's offscreen platform: snapshots and feedback from a real
// capture session drive the banner, the step list, the device chips and the feedback line.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <QApplication>
#include <QChart>
#include <QChartView>
#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFile>
#include <QGraphicsScene>
#include <QGraphicsSimpleTextItem>
#include <QGraphicsTextItem>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMessageBox>
#include <QPushButton>
#include <QRegularExpression>
#include <QScrollBar>
#include <QSettings>
#include <QShortcut>
#include <QTableWidget>
#include <QTest>
#include <QTreeWidget>
#include <QValueAxis>
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <set>
#include <thread>

#include "../../../tests/support/pg_cluster.hpp"
#include "capture/setup_dialog.hpp"
#include "dialogs/settings_dialog.hpp"
#include "field/field_view.hpp"
#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/leaf_export.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/run/capture_run.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/acquisition/sim/plant_simulation.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/devices/sim/field_distortion.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/leaf2d/leaf_scan.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "plant/plant_capture_view.hpp"
#include "plant/plant_setup_dialog.hpp"
#include "plant/plant_view.hpp"
#include "preview/mesh_choice.hpp"
#include "review/correction_dialog.hpp"
#include "review/export_dialog.hpp"
#include "review/review_view.hpp"
#include "station_window.hpp"

namespace acq = leafdig::acquisition;
namespace fs = std::filesystem;
namespace m = leafdig::model;

namespace {

constexpr std::int64_t kMs = 1'000'000;

// The ThreadSanitizer pass runs the station without Qt Multimedia (whose sample-cache
// threads are not built with TSan, tests/tsan-qt.supp): LEAFDIG_TEST_NO_AUDIO=1.
bool audio() {
  return std::getenv("LEAFDIG_TEST_NO_AUDIO") == nullptr;
}

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
  const auto leaf =
      leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");

  leafdig::station::StationOptions options;
  options.audio = audio();
  options.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(options);
  EXPECT_TRUE(w.windowTitle().startsWith("leafdig"));
  w.applySnapshot(session.snapshot());
  EXPECT_EQ(w.bannerText().toStdString(), "Tip: touch the leaf tip and press");
  std::int64_t t = 0;
  ASSERT_EQ(press(session, t, leaf.tipMm).at(0).kind, acq::Feedback::Kind::Accepted);
  for (int c = 0; c < 7; ++c)
    ASSERT_EQ(press(session, t, leaf.rows[0].pointsMm[static_cast<std::size_t>(c)]).at(0).kind,
              acq::Feedback::Kind::Accepted);
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

std::string slurpText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path freshDir(const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-station-" + tag + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A complete leaf in `store` (its first `rows` rows), captured through a real session.
// `shown` sees every snapshot along the way.
std::int64_t completeLeaf(leafdig::db::Store& store, std::optional<double> areaMm2 = {}, std::size_t rows = 3,
                          const std::function<void(const acq::Snapshot&)>& shown = {},
                          const std::string& station = {}) {
  const auto leaf =
      leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");
  acq::SessionSetup setup;
  setup.project = "p";
  setup.plant = "pl";
  setup.measuredAreaMm2 = areaMm2;
  setup.station = station;
  const auto id = acq::CaptureSession::create(store, setup);
  acq::CaptureSession s(store, id);
  std::int64_t t = 0;
  (void)press(s, t, leaf.tipMm);
  if (shown) shown(s.snapshot());
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < 7; ++c) {
      (void)press(s, t, leaf.rows[r].pointsMm[c]);
      if (shown) shown(s.snapshot());
    }
  (void)s.endRows(t);
  if (shown) shown(s.snapshot());
  for (std::size_t r = 0; r < rows; ++r) {
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
  s.engine.relocationToleranceMm = 0.8;
  s.fieldCheckMaxAgeHours = 48;
  s.save(file);
  QStringList problems;
  auto back = leafdig::station::StationSettings::load(file, &problems);
  EXPECT_TRUE(problems.isEmpty()) << problems.join("; ").toStdString();
  EXPECT_EQ(back.units, "in");
  EXPECT_EQ(back.theme, "dark");
  EXPECT_DOUBLE_EQ(back.fontScale, 1.6);
  EXPECT_EQ(back.shortcuts[leafdig::station::Action::Undo], QKeySequence(Qt::Key_F5));
  EXPECT_EQ(back.engine.stillWindowNs, 400'000'000);
  EXPECT_DOUBLE_EQ(back.engine.relocationToleranceMm, 0.8);
  EXPECT_DOUBLE_EQ(back.fieldCheckMaxAgeHours, 48);
  EXPECT_EQ(back.length(25.4, 2), "1.000 in");
  {
    QSettings q(file, QSettings::IniFormat);
    q.setValue("display/theme", "purple");
    q.setValue("display/font_scale", "huge");
    q.setValue("capture/still_window_ms", 99999);
    q.setValue("capture/relocation_tolerance_mm", 0);
    q.setValue("field/max_check_age_hours", "a week");
  }
  back = leafdig::station::StationSettings::load(file, &problems);
  EXPECT_EQ(problems.size(), 5) << problems.join("; ").toStdString();
  EXPECT_DOUBLE_EQ(back.fieldCheckMaxAgeHours, acq::kFieldCheckMaxAgeHours);
  EXPECT_DOUBLE_EQ(back.engine.relocationToleranceMm, acq::Settings().relocationToleranceMm);
  EXPECT_EQ(back.theme, "light");
  EXPECT_DOUBLE_EQ(back.fontScale, leafdig::station::StationSettings().fontScale);
  // The dialog edits every field it shows.
  leafdig::station::SettingsDialog d(back);
  d.units()->setCurrentIndex(d.units()->findData("mm"));
  d.theme()->setCurrentIndex(d.theme()->findData("dark"));
  d.sounds()->setChecked(false);
  d.shortcut(leafdig::station::Action::Pause)->setKeySequence(QKeySequence(Qt::Key_F9));
  d.stillWindowMs()->setValue(300);
  d.relocationToleranceMm()->setValue(2.5);
  d.fieldCheckMaxAgeHours()->setValue(72);
  const auto r = d.result();
  EXPECT_DOUBLE_EQ(r.fieldCheckMaxAgeHours, 72);
  EXPECT_EQ(r.units, "mm");
  EXPECT_EQ(r.theme, "dark");
  EXPECT_FALSE(r.sounds);
  EXPECT_EQ(r.shortcuts.at(leafdig::station::Action::Pause), QKeySequence(Qt::Key_F9));
  EXPECT_EQ(r.engine.stillWindowNs, 300'000'000);
  EXPECT_DOUBLE_EQ(r.engine.relocationToleranceMm, 2.5);
  fs::remove_all(dir);
}

// The lab URL's password is never stored (issue 47, 13): saving strips it, the file is the
// owner's alone (0600), a file that holds one from before is read without it and says so.
TEST(StationSettings, TheLabPasswordIsNeverStoredAndTheFileIsTheOwnersAlone) {
  const fs::path dir = freshDir("settings-secret");
  const QString file = QString::fromStdString((dir / "s.ini").string());
  leafdig::station::StationSettings s;
  s.labUrl = "postgresql://greenhouse2:s3cret@lab.example:5432/leafdig?sslmode=verify-full";
  s.save(file);
  const std::string text = slurpText(dir / "s.ini");
  EXPECT_EQ(text.find("s3cret"), std::string::npos) << text;
  EXPECT_NE(text.find("greenhouse2@lab.example"), std::string::npos) << text;
  EXPECT_EQ(fs::status(dir / "s.ini").permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  for (const char* url :
       {"postgresql://tech@lab.example/leafdig?password=s3cret", "postgresql://tech:s3cret@lab.example/leafdig"}) {
    {
      QSettings q(file, QSettings::IniFormat);
      q.setValue("lab/url", url);
    }
    QStringList problems;
    const auto back = leafdig::station::StationSettings::load(file, &problems);
    EXPECT_EQ(back.labUrl.toStdString().find("s3cret"), std::string::npos) << back.labUrl.toStdString();
    EXPECT_NE(back.labUrl.toStdString().find("tech@lab.example"), std::string::npos) << back.labUrl.toStdString();
    ASSERT_EQ(problems.size(), 1);
    EXPECT_NE(problems.front().toStdString().find("~/.pgpass"), std::string::npos);
  }
  // The dialog hands back a URL without the password.
  leafdig::station::StationSettings withSecret;
  withSecret.labUrl = "postgresql://tech:s3cret@lab.example/leafdig";
  leafdig::station::SettingsDialog d(withSecret);
  EXPECT_EQ(d.result().labUrl.toStdString().find("s3cret"), std::string::npos);
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
  // Preloaded: every cue leaves Loading within seconds (Ready with an output, Error without).
  QElapsedTimer t;
  t.start();
  while (sounds.loading() && t.elapsed() < 10000) QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
  EXPECT_FALSE(sounds.loading()) << "a cue's sound was still loading after 10 s";
  EXPECT_NE(sounds.status(leafdig::station::Cue::Accept), QSoundEffect::Null);
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
  // ... or from a scan of the leaf: a 60 x 40 mm ellipse at 300 DPI, 1885 mm² (18.85 cm²).
  {
    const auto scan =
        std::filesystem::temp_directory_path() / ("leafdig-setup-scan-" + std::to_string(::getpid()) + ".png");
    std::vector<Eigen::Vector2d> ellipse;
    for (int i = 0; i < 1024; ++i) {
      const double t = 2 * M_PI * i / 1024;
      ellipse.emplace_back(50 + 30 * std::cos(t), 40 + 20 * std::sin(t));
    }
    leafdig::model::renderScan({ellipse}, {}, {100, 80}, 300, scan);
    QString scanProblem;
    ASSERT_TRUE(d.areaFromScan(QString::fromStdString(scan.string()), 300, &scanProblem)) << scanProblem.toStdString();
    const auto fromScan = d.choice(&problem);
    ASSERT_TRUE(fromScan.has_value()) << problem.toStdString();
    EXPECT_NEAR(*fromScan->setup.measuredAreaMm2, 1024 / 2.0 * 30 * 20 * std::sin(2 * M_PI / 1024), 0.01 * 1885);
    EXPECT_FALSE(d.areaFromScan("/nonexistent/scan.png", 300, &scanProblem));
    EXPECT_TRUE(scanProblem.contains("no such image")) << scanProblem.toStdString();
    std::filesystem::remove(scan);
    d.measuredArea()->setText("512.5");
  }
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
  c.reason = "caliper jaws on the vein, not <b>beside</b> it";
  EXPECT_TRUE(v.decisionsEnabled());  // a complete session, shown whole
  EXPECT_TRUE(v.correct(c).isEmpty());
  // Who corrected what is shown with the metrics (issue 49).
  EXPECT_TRUE(v.metricsText().contains("Review:")) << v.metricsText().toStdString();
  EXPECT_TRUE(v.metricsText().contains("corrected vein_origin_thickness row 2 point 4: "))
      << v.metricsText().toStdString();
  EXPECT_TRUE(v.metricsText().contains("→ 0.900 mm by curator at ")) << v.metricsText().toStdString();
  // A reason from the file is shown as the text it is, never as markup.
  bool plain = false;
  for (const QLabel* l : v.findChildren<QLabel*>())
    if (l->text() == v.metricsText()) plain = l->textFormat() == Qt::PlainText;
  EXPECT_TRUE(plain);
  bool flagged = false;
  for (int r = 0; r < v.markersTable()->rowCount(); ++r)
    flagged = flagged || v.markersTable()->item(r, 5)->text().startsWith("corrected: caliper jaws");
  EXPECT_TRUE(flagged);
  EXPECT_GE(v.flagsList()->count(), 1);
  // Step-by-step replay through the same engine.
  v.replayTo(5);
  EXPECT_TRUE(v.bannerText().contains("replay at event 5")) << v.bannerText().toStdString();
  EXPECT_FALSE(v.decisionsEnabled());  // an earlier state is not what a curator decides on
  EXPECT_LT(v.markersTable()->rowCount(), 6);
  v.replaySlider()->setValue(v.replaySlider()->maximum());
  EXPECT_EQ(v.markersTable()->rowCount(), 1 + 21 + 6 + 1);
  // Approve needs a name; then the session is approved and final.
  EXPECT_FALSE(v.approve("").isEmpty());
  EXPECT_TRUE(v.decisionsEnabled());
  EXPECT_TRUE(v.approve("curator").isEmpty());
  EXPECT_TRUE(v.bannerText().contains("approved")) << v.bannerText().toStdString();
  EXPECT_FALSE(v.decisionsEnabled());  // approved stands: Correct, Approve and Reject are off
  EXPECT_TRUE(v.metricsText().contains("approved by curator at ")) << v.metricsText().toStdString();
  EXPECT_FALSE(v.reject("curator", "late").isEmpty());
  // Until a curator reopens it with a reason: complete again, decided anew.
  EXPECT_TRUE(v.reopenEnabled());
  EXPECT_FALSE(v.reopen("curator", "").isEmpty());
  EXPECT_TRUE(v.bannerText().contains("say why the session is reopened")) << v.bannerText().toStdString();
  EXPECT_TRUE(v.reopen("second curator", "the tip was misplaced").isEmpty());
  EXPECT_TRUE(v.decisionsEnabled());
  EXPECT_FALSE(v.reopenEnabled());
  EXPECT_TRUE(v.metricsText().contains("reopened (was approved) by second curator at "))
      << v.metricsText().toStdString();
  EXPECT_TRUE(v.metricsText().contains(": the tip was misplaced")) << v.metricsText().toStdString();
  EXPECT_TRUE(v.reject("second curator", "late").isEmpty());
  EXPECT_TRUE(v.reopenEnabled());
  EXPECT_FALSE(v.openSession(open + 50));
  EXPECT_TRUE(v.bannerText().contains("no session")) << v.bannerText().toStdString();
  fs::remove_all(dir);
}

// A curator reviews a station's file without starting a capture (issue 49): the window opens
// its Review tab on the file at once; the plant sessions in it are named, with where to review
// them.
TEST(StationWindow, TheReviewTabOpensTheFileWithoutACaptureAndPointsToThePlants) {
  const fs::path dir = freshDir("review-at-start");
  const fs::path file = dir / "s.sqlite";
  fs::copy_file(fs::path(LEAFDIG_SOURCE_DIR) / "tests/data/legacy/station-schema2.sqlite", file);
  leafdig::station::StationOptions options;
  options.audio = audio();
  options.db = file.string();
  options.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(options);
  w.tabs()->setCurrentWidget(w.review());
  ASSERT_EQ(w.review()->sessionsTable()->rowCount(), 1);  // the leaf; the plant is the Plant tab's
  EXPECT_EQ(w.review()->sessionsTable()->item(0, 4)->text(), "complete");
  EXPECT_TRUE(w.review()->plantNote().contains("1 plant session")) << w.review()->plantNote().toStdString();
  EXPECT_TRUE(w.review()->plantNote().contains("Plant tab")) << w.review()->plantNote().toStdString();
  EXPECT_FALSE(w.review()->decisionsEnabled());  // nothing open yet
  ASSERT_TRUE(w.review()->openSession(1));
  EXPECT_TRUE(w.review()->decisionsEnabled());
  // For a person to look at: LEAFDIG_TEST_SCREENSHOTS=DIR saves the tab after a correction and
  // an approval.
  if (const char* shots = std::getenv("LEAFDIG_TEST_SCREENSHOTS")) {
    acq::Correction c;
    c.what = acq::What::MidribThickness;
    c.row = 2;
    c.col = 4;
    c.valueMm = 1.25;
    c.who = "carla";
    c.reason = "misread";
    EXPECT_TRUE(w.review()->correct(c).isEmpty());
    EXPECT_TRUE(w.review()->approve("carla").isEmpty());
    w.resize(1366, 768);
    w.show();
    QCoreApplication::processEvents();
    EXPECT_TRUE(w.grab().save(QString::fromStdString((fs::path(shots) / "review-tab.png").string())));
  }
  fs::remove_all(dir);
}

// A station file from someone else (issue 25): a copy with a trigger added is not opened,
// the view says why and the file is unchanged; a marker moved behind its event shows as a
// broken chain naming the item, and cannot be approved.
TEST(ReviewView, ACraftedCopyOfAStationFileIsRefusedByNameAndAnEditedOneCannotBeApproved) {
  const fs::path dir = freshDir("review-crafted");
  const std::string db = (dir / "s.sqlite").string();
  std::int64_t id = 0;
  {
    leafdig::db::Store store(db);
    id = completeLeaf(store, 40000.0);
  }
  const auto sql = [](const std::string& file, const std::string& statement) {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &h), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(h, statement.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(h);
  };
  const std::string trigger = (dir / "trigger.sqlite").string();
  fs::copy_file(db, trigger);
  sql(trigger, "CREATE TRIGGER evil AFTER INSERT ON events BEGIN UPDATE markers SET x_mm = x_mm + 100; END;");
  const auto bytes = [](const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string before = bytes(trigger);
  {
    leafdig::station::ReviewView v(leafdig::station::StationSettings{});
    v.setDatabase(trigger);
    EXPECT_EQ(v.sessionsTable()->rowCount(), 0);
    EXPECT_TRUE(v.bannerText().contains("cannot open")) << v.bannerText().toStdString();
    EXPECT_TRUE(v.bannerText().contains("an extra trigger 'evil' on 'events'")) << v.bannerText().toStdString();
    EXPECT_FALSE(v.openSession(id));
  }
  EXPECT_EQ(bytes(trigger), before);
  const std::string moved = (dir / "moved.sqlite").string();
  fs::copy_file(db, moved);
  sql(moved, "UPDATE markers SET x_mm = x_mm + 100 WHERE row = 2 AND col = 2");
  leafdig::station::ReviewView v(leafdig::station::StationSettings{});
  v.setDatabase(moved);
  ASSERT_TRUE(v.openSession(id));
  EXPECT_TRUE(v.bannerText().contains("the markers table has marker row 2 col 2")) << v.bannerText().toStdString();
  EXPECT_FALSE(v.approve("curator").isEmpty());
  EXPECT_EQ(leafdig::db::Store(moved, true).session(id)->status, "complete");
  fs::remove_all(dir);
}

// A throw-away lab server (started for the test) with the schema, a technician bound to
// `station` and a curator: their URLs (passwords pw-t and pw-c).
struct TestLab {
  leafdig::test::PgCluster cluster;
  std::string database = cluster.createDatabase();
  std::string tech = cluster.url("tech", "pw-t", database);
  std::string curator = cluster.url("carla", "pw-c", database);

  explicit TestLab(const std::string& station) {
    const std::string admin = cluster.adminUrl(database);
    (void)leafdig::db::initServer(admin);
    (void)leafdig::db::addUser(admin, "tech", leafdig::db::LabRole::Technician, station, std::string("pw-t"));
    (void)leafdig::db::addUser(admin, "carla", leafdig::db::LabRole::Curator, "", std::string("pw-c"));
  }
};

TEST(ReviewView, TheLabServersSessionsAreReviewedFromTheStationAndTheDecisionGoesBack) {
  // A real PostgreSQL server (started for this test), a station's session pushed to it, and
  // the review view on the server's URL as a curator opens it (leafdig-station --db URL).
  const TestLab lab("bench-w");
  const std::string& tech = lab.tech;
  const std::string& curator = lab.curator;
  const fs::path dir = freshDir("review-lab");
  leafdig::db::Store station((dir / "s.sqlite").string());
  const std::int64_t id = completeLeaf(station, 40000.0, 3, {}, "bench-w");
  const std::int64_t second = completeLeaf(station, 40000.0, 3, {}, "bench-w");
  ASSERT_TRUE(leafdig::db::push(station, tech).problems.empty());

  leafdig::station::ReviewView v(leafdig::station::StationSettings{});
  v.resize(1400, 900);
  v.setDatabase(curator);
  ASSERT_EQ(v.sessionsTable()->rowCount(), 2);  // newest first
  EXPECT_EQ(v.sessionsTable()->item(1, 8)->text().toStdString(), "bench-w:" + std::to_string(id));
  EXPECT_EQ(v.sessionsTable()->item(0, 8)->text().toStdString(), "bench-w:" + std::to_string(second));
  const std::int64_t serverId = v.sessionsTable()->item(1, 0)->text().toLongLong();
  const std::int64_t serverSecond = v.sessionsTable()->item(0, 0)->text().toLongLong();
  ASSERT_TRUE(v.openSession(serverId));
  EXPECT_TRUE(v.bannerText().contains("chain OK")) << v.bannerText().toStdString();
  EXPECT_EQ(v.markersTable()->rowCount(), 1 + 21 + 6 + 1);
  EXPECT_TRUE(v.approve("carla").isEmpty()) << v.bannerText().toStdString();
  EXPECT_TRUE(v.bannerText().contains("approved")) << v.bannerText().toStdString();
  // A technician's view of the same session: the server refuses the approval, and says so.
  leafdig::station::ReviewView t(leafdig::station::StationSettings{});
  t.setDatabase(tech);
  ASSERT_TRUE(t.openSession(serverSecond));
  EXPECT_FALSE(t.approve("tom").isEmpty());
  EXPECT_TRUE(t.bannerText().contains("only curators review")) << t.bannerText().toStdString();
  // The station takes the decision in.
  EXPECT_EQ(leafdig::db::pull(station, tech).eventsTaken, 1);
  EXPECT_EQ(station.session(id)->status, "approved");
  EXPECT_EQ(station.session(second)->status, "complete");
  fs::remove_all(dir);
}

TEST(StationWindow, SyncsWithTheLabServerOfItsSettingsAndShowsTheCuratorsDecision) {
  TestLab lab("bench-s");
  const fs::path dir = freshDir("sync-lab");
  const std::string file = (dir / "s.sqlite").string();
  std::int64_t id = 0;
  {
    leafdig::db::Store store(file);
    id = completeLeaf(store, 40000.0, 3, {}, "bench-s");
  }
  // The lab server in the station's settings, set through the settings dialog.
  const QString ini = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationSettings settings;
  leafdig::station::SettingsDialog d(settings);
  d.labUrl()->setText(QString::fromStdString(lab.tech));
  d.labSyncMinutes()->setValue(15);
  d.result().save(ini);
  EXPECT_EQ(leafdig::station::StationSettings::load(ini).labSyncMinutes, 15);

  // The station keeps no password (issue 47): it comes from libpq's environment, as from
  // ~/.pgpass at a real station.
  EXPECT_EQ(slurpText(dir / "station.ini").find("pw-t"), std::string::npos);
  qputenv("PGPASSWORD", "pw-t");
  struct Unset {
    ~Unset() { qunsetenv("PGPASSWORD"); }
  } unset;
  leafdig::station::StationOptions options;
  options.audio = audio();
  options.db = file;
  options.settingsFile = ini;
  leafdig::station::StationWindow w(options);
  w.syncWithLab();
  QTRY_VERIFY_WITH_TIMEOUT(!w.syncing(), 30000);
  EXPECT_TRUE(w.labStatusText().contains("sent")) << w.labStatusText().toStdString();
  leafdig::db::LabStore curator(lab.curator);
  ASSERT_EQ(curator.sessions().size(), 1u);
  EXPECT_EQ(curator.sessions()[0].headSeq, leafdig::db::Store(file, true).session(id)->headSeq);
  // A curator approves on the server; the next sync brings it to the station's file and review.
  (void)curator.setStatus(curator.sessions()[0].id, "approved", "carla", "");
  w.syncWithLab();
  QTRY_VERIFY_WITH_TIMEOUT(!w.syncing(), 30000);
  EXPECT_TRUE(w.labStatusText().contains("took in 1 decision")) << w.labStatusText().toStdString();
  EXPECT_EQ(leafdig::db::Store(file, true).session(id)->status, "approved");
  bool shown = false;
  for (int r = 0; r < w.review()->sessionsTable()->rowCount(); ++r)
    shown = shown || w.review()->sessionsTable()->item(r, 4)->text() == "approved";
  EXPECT_TRUE(shown);
  // A server that cannot be reached: said, nothing else happens.
  auto unreachable = w.settings();
  unreachable.labUrl =
      QString::fromStdString(lab.cluster.url("tech", "pw-t", lab.database, leafdig::test::freeLocalPort()));
  w.applySettings(unreachable);
  w.syncWithLab();
  QTRY_VERIFY_WITH_TIMEOUT(!w.syncing(), 30000);
  EXPECT_TRUE(w.labStatusText().contains("not synced")) << w.labStatusText().toStdString();
  EXPECT_FALSE(w.labStatusText().contains("pw-t")) << "the password stays out of the window";
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
  EXPECT_EQ(result.written.size(), 4u);  // glb + three CSVs (markers, thickness, metrics)
  ASSERT_EQ(result.failed.size(), 1u);
  EXPECT_EQ(result.failed[0].first, unfinished);
  EXPECT_EQ(calls, 3);
  for (const auto& p : result.written) EXPECT_TRUE(fs::exists(p)) << p;
  // The complete session nobody approved is named (issue 49); once approved, it is not.
  ASSERT_EQ(result.unapproved.size(), 1u);
  EXPECT_EQ(result.unapproved[0], (std::pair<std::int64_t, std::string>{done, "complete"}));
  EXPECT_EQ(leafdig::station::unapprovedWarning(result).toStdString(),
            "Not approved by a curator: session " + std::to_string(done) +
                " (complete) — their numbers are as captured, unchecked.");
  {
    leafdig::db::Store store(db);
    (void)acq::review(store, done, "approved", "carla", "checked");
  }
  fs::remove_all(dir / "out");
  const auto approved = leafdig::station::exportBatch(db, {done}, r, [](int, int, const QString&) { return true; });
  EXPECT_EQ(approved.written.size(), 4u);
  EXPECT_TRUE(approved.unapproved.empty());
  EXPECT_TRUE(leafdig::station::unapprovedWarning(approved).isEmpty());
  fs::remove_all(dir / "out");
  const auto cancelled =
      leafdig::station::exportBatch(db, {done, unfinished}, r, [](int, int, const QString&) { return false; });
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
  EXPECT_EQ(req.mesh, "uniform");
  // Adaptive meshing from the dialog: far fewer triangles in the exported OBJ.
  EXPECT_FALSE(d.mesh()->maxError()->isEnabled());
  d.mesh()->method()->setCurrentIndex(d.mesh()->method()->findData("adaptive"));
  EXPECT_TRUE(d.mesh()->maxError()->isEnabled());
  EXPECT_FALSE(d.mesh()->minLength()->isEnabled());
  d.mesh()->maxError()->setValue(0.25);
  const auto adaptive = d.request();
  EXPECT_EQ(adaptive.mesh, "adaptive");
  EXPECT_DOUBLE_EQ(adaptive.maxErrorMm, 0.25);
  const auto faces = [](const std::string& path) {
    std::ifstream in(path);
    std::size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.rfind("f ", 0) == 0;
    return n;
  };
  leafdig::db::Store store(db);
  const auto uniformFile = acq::exportSession(store, done, req).written.at(0);
  const std::size_t uniformFaces = faces(uniformFile);
  fs::remove(uniformFile);
  const auto adaptiveFile = acq::exportSession(store, done, adaptive).written.at(0);
  EXPECT_GT(faces(adaptiveFile), 200u);
  EXPECT_LT(faces(adaptiveFile), uniformFaces / 5);
  fs::remove_all(dir);
}

TEST(StationWindow, SimulatedDevicesShowRateAndAgeAndGoOffLineFromTheirChip) {
  const fs::path dir = freshDir("devices");
  leafdig::station::StationOptions o;
  o.audio = audio();
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
  EXPECT_TRUE(waitFor([&] { return w.chipText(Role::Digitizer).contains("Hz"); }))
      << w.chipText(Role::Digitizer).toStdString();
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

// Issue 50: the station's simulated digitizer reports through a bent field (`--distortion`):
// here one that moves every point 3 mm along x, 2 mm back along y and 1 mm up, so the leaf's tip
// is stored there and the virtual technician, judging by the screen, goes on to the first row.
TEST(StationWindow, TheSimulatedDigitizerReportsThroughABentField) {
  const fs::path dir = freshDir("field");
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.speed = 20;
  o.markers = std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json";
  o.setup.project = "p";
  o.setup.plant = "pl";
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::devices::sim::FieldDistortion field;
  field.originMm = {-1000, -1000, -1000};
  field.spacingMm = 1000;
  field.shape = {2, 2, 2};
  field.displacementMm.assign(8, {3, -2, 1});
  o.distortion = std::make_shared<const leafdig::devices::sim::FieldDistortion>(field);
  leafdig::station::StationWindow w(o);
  ASSERT_TRUE(w.start()) << w.bannerText().toStdString();
  const auto rowOneBegun = [&] {
    const auto& s = w.lastSnapshot();
    return s && s->items.size() >= 2;
  };
  for (int i = 0; i < 1500 && !rowOneBegun(); ++i) QTest::qWait(20);
  ASSERT_TRUE(rowOneBegun()) << w.bannerText().toStdString();
  const auto truth = leafdig::model::readMarkersFile(o.markers).tipMm;
  const acq::Item& tip = w.lastSnapshot()->items.front();
  ASSERT_EQ(tip.what, acq::What::Tip);
  EXPECT_NEAR(tip.positionMm[0], truth.x() + 3, 1.0);
  EXPECT_NEAR(tip.positionMm[1], truth.y() - 2, 1.0);
  EXPECT_NEAR(tip.positionMm[2], truth.z() + 1, 1.0);
  w.stopCapture();
  fs::remove_all(dir);
}

// Issue 50: a capture at the station through a checked field (`--field-calibration`): refused in
// words when the file holds no check, and with one, the session keeps the check it went through.
TEST(StationWindow, ACaptureGoesThroughTheCheckedFieldItWasStartedWith) {
  const fs::path dir = freshDir("field-check");
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.speed = 20;
  o.setup.project = "p";
  o.setup.plant = "pl";
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  o.fieldCalibration = "latest";
  {
    leafdig::station::StationWindow w(o);
    EXPECT_FALSE(w.start());
    EXPECT_TRUE(w.bannerText().contains("no field check in")) << w.bannerText().toStdString();
  }
  // A check of a field that stretches x by 0.5 %: correctable, the correction affine.
  leafdig::model::Jig jig{"cube", {}};
  for (double z : {0.0, 100.0})
    for (double y : {0.0, 200.0})
      for (double x : {0.0, 150.0, 300.0})
        jig.points.push_back({"D" + std::to_string(jig.points.size() + 1), {x, y, z}});
  std::vector<acq::JigPress> presses;
  std::vector<acq::Vec3> points;
  for (const auto& p : jig.points) {
    presses.push_back({{p.pointMm.x() * 1.005, p.pointMm.y(), p.pointMm.z() - 0.01 * p.pointMm.x()}, "01", 0});
    points.push_back(presses.back().positionMm);
  }
  const acq::FieldCheckResult r = acq::checkField(jig, points, 0.2);
  ASSERT_EQ(r.verdict, "correctable");
  {
    leafdig::db::Store store(o.db);
    store.addFieldCheck({"st", "ana", "fastrak", "simulated", r.verdict, acq::encodeFieldCheck(jig, presses, r, "x")});
  }
  leafdig::station::StationWindow w(o);
  ASSERT_TRUE(w.start()) << w.bannerText().toStdString();
  // The Capture tab says which check corrects it (LEAFDIG_TEST_SCREENSHOTS=DIR: the tab, to look at).
  EXPECT_TRUE(w.fieldText().startsWith("field: corrected by field check 1 ")) << w.fieldText().toStdString();
  if (const char* shots = std::getenv("LEAFDIG_TEST_SCREENSHOTS")) {
    w.resize(1400, 900);
    w.show();
    QTest::qWait(300);
    EXPECT_TRUE(w.grab().save(QString::fromStdString((fs::path(shots) / "capture-field.png").string())));
  }
  const std::int64_t id = w.sessionId();
  w.stopCapture();
  leafdig::db::Store store(o.db, true);
  const auto field = acq::fieldAppliedFromSettings(store.session(id)->settingsJson, "session");
  ASSERT_TRUE(field);
  EXPECT_EQ(field->id, 1);
  EXPECT_EQ(field->correction.degree, r.correction.correction.degree);
  fs::remove_all(dir);
}

// Issue 29: a technician moves the transmitter in a leaf's capture with the station's key
// (Ctrl+M, in the settings' shortcuts): the steps list and the banner ask for the three board
// points again, the virtual technician moves the simulated transmitter and takes them, the fit is
// announced, and the leaf comes out in the first position's frame.
TEST(StationWindow, ATechnicianMovesTheTransmitterOfALeafWithTheKey) {
  const fs::path dir = freshDir("leaf-move");
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.speed = 10;
  o.setup.project = "p";
  o.setup.plant = "pl";
  o.setup.settings.boardFrame = true;
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(o);
  EXPECT_EQ(w.settings().shortcuts.at(leafdig::station::Action::MoveTransmitter),
            QKeySequence(Qt::Key_M | Qt::ControlModifier));
  ASSERT_TRUE(w.start()) << w.bannerText().toStdString();
  const auto waitFor = [&](const std::function<bool()>& ok, int seconds = 60) {
    for (int i = 0; i < seconds * 50 && !ok(); ++i) QTest::qWait(20);
    return ok();
  };
  const auto step = [&] { return w.lastSnapshot() ? w.lastSnapshot()->step : acq::Step{}; };
  ASSERT_TRUE(waitFor([&] { return step().what == acq::What::Marker && step().row == 2; }))
      << w.bannerText().toStdString();
  // The key as the station binds it: its window shortcut for Ctrl+M, activated as a key press on
  // the active window activates it (the window is not shown: showing it under ThreadSanitizer
  // reports a race inside Qt's own rendering threads).
  QShortcut* key = nullptr;
  for (QShortcut* s : w.findChildren<QShortcut*>())
    if (s->key() == QKeySequence(Qt::Key_M | Qt::ControlModifier)) key = s;
  ASSERT_NE(key, nullptr) << "no shortcut for Ctrl+M";
  emit key->activated();
  ASSERT_TRUE(waitFor([&] { return step().what == acq::What::BoardAgain; })) << w.bannerText().toStdString();
  EXPECT_TRUE(w.bannerText().startsWith("Transmitter moved · board point")) << w.bannerText().toStdString();
  const QStringList lines = texts(w.findChild<QListWidget*>("steps"));
  EXPECT_TRUE(lines.filter("Transmitter moved · board points again").size() == 1) << lines.join(" | ").toStdString();
  // The feedback line says each step of the move; the fit's words are checked here, as shown.
  acq::Feedback fit;
  fit.kind = acq::Feedback::Kind::Relocation;
  fit.text = "fitted";
  fit.relocation = 1;
  fit.fitRmsMm = 0.12;
  fit.fitWorstPoint = 2;
  w.applyFeedback(fit);
  bool said = false;
  for (const auto* l : w.findChildren<QLabel*>())
    said = said || l->text().contains("transmitter position 2 fitted: RMS 0.12 mm, worst board point 2");
  EXPECT_TRUE(said);
  ASSERT_TRUE(waitFor([&] { return w.lastSnapshot() && w.lastSnapshot()->complete; }, 120))
      << w.bannerText().toStdString();
  w.stopCapture();
  const leafdig::db::Store store(o.db, true);
  const acq::ReviewedSession r = acq::openForReview(store, w.sessionId());
  EXPECT_EQ(r.engine.transmitterPositions(), 2);
  const auto leaf =
      leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");
  for (std::size_t row = 0; row < leaf.rows.size(); ++row)
    for (int col = 1; col <= 7; ++col) {
      const acq::Item* i = acq::findItem(r.engine.items(), acq::What::Marker, static_cast<int>(row) + 1, col);
      ASSERT_NE(i, nullptr);
      const Eigen::Vector3d& want = leaf.rows[row].pointsMm[static_cast<std::size_t>(col - 1)];
      EXPECT_LT(acq::distanceMm(i->positionMm, {want.x(), want.y(), want.z()}), 1.5) << row + 1 << "," << col;
    }
  fs::remove_all(dir);
}

// The capture run's snapshots come from two threads (the loop, and the preview worker whose
// meshes they carry). The window takes them through one locked slot: a burst is applied once,
// newest last, and what the worker built is handed over under a lock ThreadSanitizer sees
// (through Qt's queue alone, the GUI thread's copy of the worker's preview raced with its
// construction: the TSan pass of the widget tests failed on it, rarely, under load).
TEST(StationWindow, SnapshotsFromTheCaptureThreadsArriveNewestLastThroughOneLockedSlot) {
  const fs::path dir = freshDir("mailbox");
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(o);
  std::mutex m;
  std::condition_variable cv;
  std::shared_ptr<const acq::Preview> built;  // the "worker" builds it, the "loop" posts it
  std::thread worker([&] {
    auto p = std::make_shared<acq::Preview>();
    p->mesh.organs.push_back({});
    const std::lock_guard lock(m);
    built = std::move(p);
    cv.notify_one();
  });
  std::thread loop([&] {
    std::shared_ptr<const acq::Preview> p;
    {
      std::unique_lock lock(m);
      cv.wait(lock, [&] { return built != nullptr; });
      p = built;
    }
    for (std::uint64_t v = 1; v <= 3; ++v) {
      acq::Snapshot s;
      s.session = 7;
      s.version = v;
      s.prompt = "step " + std::to_string(v);
      s.preview = p;
      s.previewVersion = 1;
      w.postSnapshot(s);
    }
  });
  // The window is not joined with the threads before it reads what they handed over.
  for (int i = 0; i < 500 && !(w.lastSnapshot() && w.lastSnapshot()->version == 3); ++i) QTest::qWait(10);
  ASSERT_TRUE(w.lastSnapshot().has_value());
  EXPECT_EQ(w.lastSnapshot()->version, 3u);
  EXPECT_EQ(w.bannerText(), "step 3");
  ASSERT_NE(w.lastSnapshot()->preview, nullptr);
  EXPECT_EQ(w.lastSnapshot()->preview->mesh.organs.size(), 1u);
  loop.join();
  worker.join();
  // Nothing older arrives after the newest.
  QApplication::processEvents();
  EXPECT_EQ(w.lastSnapshot()->version, 3u);
  fs::remove_all(dir);
}

// The sample plant digitized into a fresh file `db` by the virtual technician through the
// simulated devices (moving the transmitter after `relocateAfter` points, when not 0): its
// session id, the session complete.
std::int64_t captureSamplePlant(const std::string& db, int relocateAfter = 0) {
  namespace acq = leafdig::acquisition;
  std::filesystem::remove(db);
  leafdig::db::Store store(db);
  acq::PlantSessionSetup setup = acq::simulatedPlantSetup(
      leafdig::model::readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json"));
  setup.project = "p";
  const std::int64_t id = acq::PlantCaptureSession::create(store, setup);
  acq::SimulationOptions sim;
  sim.speed = 40;
  sim.mistakes = false;
  sim.relocateSourceAfter = relocateAfter;
  const std::atomic<bool> stop{false};
  (void)acq::runSimulatedPlant(store, id, sim, {}, stop);
  EXPECT_EQ(store.session(id)->status, "complete");
  return id;
}

}  // namespace

// Every step, table cell and axis title shows whole at the screen sizes stations use.
TEST(StationLayout, NothingIsCutOffAt1366x768And1920x1080) {
  const fs::path dir = freshDir("layout");
  const std::string db = (dir / "s.sqlite").string();
  std::int64_t id = 0;
  std::optional<acq::Snapshot> last;
  {
    leafdig::db::Store store(db);
    id = completeLeaf(store, 40000.0, 10, [&](const acq::Snapshot& s) { last = s; });
  }
  leafdig::station::StationOptions options;
  options.audio = audio();
  options.settingsFile = QString::fromStdString((dir / "station.ini").string());
  options.db = db;
  for (const QSize size : {QSize(1366, 768), QSize(1920, 1080)}) {
    SCOPED_TRACE(std::to_string(size.width()) + "x" + std::to_string(size.height()));
    leafdig::station::StationWindow w(options);
    w.resize(size);
    w.show();
    // The capture view after the last row and the end of the rows: every row's thickness step.
    {
      leafdig::db::Store store(db, true);
      const auto r = acq::openForReview(store, id);
      acq::Snapshot s = *last;
      s.items = r.engine.items();
      s.plan = r.engine.plan();
      s.step = r.engine.step();
      s.prompt = r.engine.prompt();
      s.rowsEnded = true;
      w.applySnapshot(s);
    }
    // A long rejection reason wraps instead of widening the window.
    acq::Feedback rejected;
    rejected.kind = acq::Feedback::Kind::Rejected;
    rejected.text =
        "the stylus moved 3.2 mm while the button was down: hold it still on the marker for half a second "
        "before pressing, then press and release without pushing the leaf";
    w.applyFeedback(rejected);
    QApplication::processEvents();
    EXPECT_LE(w.width(), size.width());
    EXPECT_LE(w.minimumSizeHint().width(), size.width());
    const auto* steps = w.findChild<QListWidget*>("steps");
    ASSERT_NE(steps, nullptr);
    ASSERT_GE(steps->count(), 20);
    const int listWidth = steps->viewport()->width();
    for (int i = 0; i < steps->count(); ++i) {
      const QListWidgetItem* item = steps->item(i);
      const QRect cellRect = steps->visualItemRect(item);
      const QRect need =
          QFontMetrics(item->font()).boundingRect(QRect(0, 0, listWidth - 8, 10000), Qt::TextWordWrap, item->text());
      EXPECT_LE(need.height(), cellRect.height()) << item->text().toStdString();
      EXPECT_LE(cellRect.right(), listWidth) << item->text().toStdString();
    }
    // The review of the same session: the markers table and the thickness chart.
    w.tabs()->setCurrentIndex(1);
    w.review()->setDatabase(db);
    ASSERT_TRUE(w.review()->openSession(id));
    QApplication::processEvents();
    // The window fits the screen: no widget's minimum size pushed it wider or taller.
    EXPECT_LE(w.width(), size.width());
    EXPECT_LE(w.height(), size.height());
    EXPECT_LE(w.minimumSizeHint().width(), size.width());
    const QTableWidget* table = w.review()->markersTable();
    const int tableWidth = table->viewport()->width();
    for (int c = 0; c < table->columnCount(); ++c) {
      const QString head = table->horizontalHeaderItem(c)->text();
      EXPECT_LE(table->columnViewportPosition(c) + table->columnWidth(c), tableWidth)
          << "column " << head.toStdString() << " is cut by the table's edge";
      EXPECT_LE(table->horizontalHeader()->fontMetrics().horizontalAdvance(head) + 8, table->columnWidth(c))
          << "header " << head.toStdString() << " does not fit";
      for (int r = 0; r < table->rowCount(); ++r) {
        const QTableWidgetItem* cellItem = table->item(r, c);
        if (!cellItem) continue;
        EXPECT_TRUE(table->fontMetrics().horizontalAdvance(cellItem->text()) <= table->columnWidth(c) ||
                    cellItem->toolTip() == cellItem->text())
            << cellItem->text().toStdString();
      }
    }
    EXPECT_FALSE(table->horizontalScrollBar()->isVisible()) << "the markers table scrolls sideways";
    QChart* chart = w.review()->chart()->chart();
    ASSERT_NE(chart, nullptr);
    // Qt Charts elides what does not fit: no label, title or legend entry may end in "…".
    int texts = 0;
    for (QGraphicsItem* item : chart->scene()->items()) {
      QString text;
      if (auto* t = dynamic_cast<QGraphicsTextItem*>(item))
        text = t->toPlainText();
      else if (auto* st = dynamic_cast<QGraphicsSimpleTextItem*>(item))
        text = st->text();
      else
        continue;
      if (!item->isVisible() || text.isEmpty()) continue;
      ++texts;
      EXPECT_FALSE(text.contains(QChar(0x2026)) || text.contains("...")) << "chart text cut: " << text.toStdString();
    }
    EXPECT_GE(texts, 8);  // the title, two axis titles, tick labels
    w.stopCapture();
  }
  fs::remove_all(dir);
}

TEST(StationLayout, ADeviceChipWrapsALongRemedyIntoShortLines) {
  leafdig::devices::DeviceStatus s;
  s.device = "Sylvac";
  s.state = leafdig::devices::LinkState::Error;
  s.message =
      "cannot open /dev/serial/by-id/usb-Prolific_Technology_Inc._USB-Serial_Controller-if00-port0: Permission denied";
  s.remedy =
      "install the udev rule (sudo cmake --install build/release --prefix /usr), then unplug and replug the gauge";
  const QString label = leafdig::station::StationWindow::chipLabel(s, acq::DeviceSet::Role::Caliper);
  EXPECT_TRUE(label.startsWith("Sylvac · error")) << label.toStdString();
  EXPECT_TRUE(label.contains("replug the gauge")) << label.toStdString();  // nothing dropped
  for (const QString& line : label.split('\n'))
    EXPECT_LE(line.size(), 110) << line.toStdString();  // one long path may stand alone on its line
  EXPECT_GE(label.count('\n'), 3);
}

TEST(StationLayout, ASimulationRunFasterThanRealTimeShowsTheDevicesOwnRate) {
  leafdig::devices::DeviceStatus s;
  s.device = "FASTRAK";
  s.state = leafdig::devices::LinkState::Streaming;
  s.rateHz = 961.0;  // 120 Hz on the wire of a simulation run 8 times faster
  s.lastSampleAgeS = 0.0;
  const QString fast = leafdig::station::StationWindow::chipLabel(s, acq::DeviceSet::Role::Digitizer, 8.0);
  EXPECT_TRUE(fast.contains("· 120 Hz (simulated ×8)")) << fast.toStdString();
  EXPECT_FALSE(fast.contains("961")) << fast.toStdString();
  const QString real = leafdig::station::StationWindow::chipLabel(s, acq::DeviceSet::Role::Digitizer);
  EXPECT_TRUE(real.contains("· 961 Hz ·")) << real.toStdString();
  EXPECT_FALSE(real.contains("simulated")) << real.toStdString();
}

// The live preview keeps the growing leaf in view, and moves only when the leaf outgrows the
// framing: every marker stays on screen, the leaf fills the view, the view does not jump.
TEST(PreviewFraming, TheGrowingLeafStaysFramedAndTheViewMovesOnlyWhenItOutgrowsIt) {
  const fs::path dir = freshDir("framing");
  leafdig::station::PreviewWidget preview;
  preview.resize(900, 600);
  int snapshots = 0;
  std::optional<leafdig::station::ViewFraming> before;
  int movedWithoutReframing = 0;
  const auto onScreen = [&](const acq::Snapshot& s, const leafdig::station::ViewFraming& f, double margin) {
    for (const auto& i : s.items) {
      if (!acq::isStylusItem(i.what)) continue;
      const QVector3D n = f.toNdc(QVector3D(static_cast<float>(i.positionMm[0]), static_cast<float>(i.positionMm[2]),
                                            static_cast<float>(-i.positionMm[1])),
                                  900.0f / 600.0f);
      if (std::abs(n.x()) > margin || std::abs(n.y()) > margin) return false;
    }
    return true;
  };
  int offScreen = 0;
  {
    leafdig::db::Store store((dir / "s.sqlite").string());
    (void)completeLeaf(store, {}, 10, [&](const acq::Snapshot& s) {
      const int changesBefore = preview.framingChanges();
      preview.show(s);
      // A move, when there is one, glides: half-way through it is neither the old nor the new view.
      if (preview.framingChanges() != changesBefore && preview.animating()) {
        preview.finishAnimation();
      } else if (before &&
                 (before->distance != preview.framing().distance || before->centre != preview.framing().centre)) {
        ++movedWithoutReframing;
      }
      offScreen += !onScreen(s, preview.framing(), 0.95);
      before = preview.framing();
      ++snapshots;
    });
  }
  std::printf("framing: %d moves over %d snapshots\n", preview.framingChanges(), snapshots);
  EXPECT_EQ(offScreen, 0);
  EXPECT_EQ(movedWithoutReframing, 0);
  EXPECT_GE(preview.framingChanges(), 2);  // it did follow the leaf…
  EXPECT_LE(preview.framingChanges(), 7);  // …without moving at every row (10 rows, 72 snapshots)
  // The whole leaf fills a good part of the view.
  const auto f = preview.framing();
  float xLo = 1, xHi = -1, yLo = 1, yHi = -1;
  const auto leaf =
      leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json");
  for (const auto& row : leaf.rows)
    for (const auto& p : row.pointsMm) {
      const QVector3D n = f.toNdc(
          QVector3D(static_cast<float>(p.x()), static_cast<float>(p.z()), static_cast<float>(-p.y())), 900.0f / 600.0f);
      xLo = std::min(xLo, n.x());
      xHi = std::max(xHi, n.x());
      yLo = std::min(yLo, n.y());
      yHi = std::max(yHi, n.y());
    }
  EXPECT_GE(std::max(xHi - xLo, yHi - yLo) / 2.0f, 0.45f) << "the leaf sits small in the view";
  // The leaf lies across the screen (tip on the left): wider than tall.
  EXPECT_GT(xHi - xLo, yHi - yLo);
  fs::remove_all(dir);
}

TEST(PlantView, APlanIsShownTheSlidersRebuildItAndItExports) {
  leafdig::station::PlantView v;
  const QString plan = QString(LEAFDIG_SOURCE_DIR) + "/data/plants/tobacco-p07.plant.json";
  ASSERT_EQ(v.openPlan(plan), QString());
  ASSERT_NE(v.plant(), nullptr);
  EXPECT_EQ(v.plant()->leaves.size(), 6u);
  EXPECT_TRUE(v.summaryText().contains("STAR")) << v.summaryText().toStdString();
  EXPECT_TRUE(v.timeSlider()->isEnabled()) << "the plan has growth";
  const double star = v.metrics()->star;
  EXPECT_GT(star, 0.3);

  // Divergence to 120°, no jitter: every azimuth follows at once (one rebuild per turn).
  v.jitterSlider()->setValue(0);
  v.divergenceSlider()->setValue(1200);
  QCoreApplication::processEvents();
  for (const auto& l : v.plant()->leaves) EXPECT_NEAR(l.azimuthDeg, std::fmod(l.rank * 120.0, 360.0), 1e-9);
  // One inclination for all leaves.
  v.inclinationSlider()->setValue(80);
  QCoreApplication::processEvents();
  for (const auto& l : v.plant()->leaves) EXPECT_DOUBLE_EQ(l.inclinationDeg, 80.0);
  // The growth scrubber at its start: only the first leaf has appeared.
  v.timeSlider()->setValue(0);
  QCoreApplication::processEvents();
  EXPECT_EQ(v.plant()->leaves.size(), 1u);
  EXPECT_TRUE(v.plant()->time.has_value());
  v.timeSlider()->setValue(v.timeSlider()->maximum());
  QCoreApplication::processEvents();
  EXPECT_FALSE(v.plant()->time.has_value()) << "the scrubber's end is the full-grown plant";

  const QString dir = QDir::tempPath() + "/leafdig-plant-view-" + QString::number(::getpid());
  QDir().mkpath(dir);
  EXPECT_EQ(v.exportTo(dir + "/plant.csv"), QString());
  QFile csv(dir + "/plant.csv");
  ASSERT_TRUE(csv.open(QIODevice::ReadOnly));
  EXPECT_EQ(csv.readAll().count('\n'), 8) << "header, stem, six leaves";
  EXPECT_FALSE(v.exportTo(dir + "/plant.xyz").isEmpty()) << "an unknown extension is refused";
  // The export's mesh is chosen beside the button: adaptive gives far fewer triangles.
  const auto objFaces = [&](const QString& name) {
    QFile f(dir + "/" + name);
    EXPECT_TRUE(f.open(QIODevice::ReadOnly));
    return f.readAll().count("\nf ");
  };
  EXPECT_EQ(v.exportTo(dir + "/uniform.obj"), QString());
  v.exportMesh()->method()->setCurrentIndex(v.exportMesh()->method()->findData("adaptive"));
  v.exportMesh()->maxError()->setValue(0.3);
  EXPECT_EQ(v.exportTo(dir + "/adaptive.obj"), QString());
  EXPECT_GT(objFaces("adaptive.obj"), 1000);
  EXPECT_LT(objFaces("adaptive.obj"), objFaces("uniform.obj") / 5);
  QDir(dir).removeRecursively();

  // A bad plan names the problem and keeps nothing half-built.
  leafdig::station::PlantView bad;
  EXPECT_TRUE(bad.openPlan(dir + "/missing.json").contains("missing.json"));
  EXPECT_EQ(bad.plant(), nullptr);
  EXPECT_TRUE(bad.planFromApprovedLeaves().contains("no database"));
}

TEST(PlantView, TheTickedApprovedLeavesOfTheStationMakeThePlant) {
  namespace acq = leafdig::acquisition;
  const std::string db =
      (QDir::tempPath() + "/leafdig-plant-lib-" + QString::number(::getpid()) + ".sqlite").toStdString();
  std::filesystem::remove(db);
  // Two complete simulated captures, approved by a curator.
  for (int position : {3, 5}) {
    acq::RunRequest r;
    r.db = db;
    r.setup.project = "p";
    r.setup.plant = "P7";
    r.setup.leafPosition = position;
    r.setup.leafType = position == 3 ? "lower" : "upper";
    r.setup.simulated = true;
    r.simulation.speed = 40;
    r.simulation.seed = static_cast<std::uint64_t>(position);
    r.simulation.mistakes = false;
    r.preview = acq::PreviewDetail::None;
    acq::CaptureRun run(r, {});
    run.start();
    run.wait();  // the virtual technician completes the leaf
    ASSERT_TRUE(run.shutdown("done").complete) << "simulated capture " << position;
  }
  {
    // Nothing approved yet: the list says so (a line that is not a leaf), and a plant of
    // the approved leaves is refused in words.
    leafdig::station::PlantView none;
    none.setDatabase(db);
    ASSERT_EQ(none.libraryList()->count(), 1);
    EXPECT_TRUE(none.libraryList()->item(0)->text().contains("approve sessions in Review"));
    EXPECT_FALSE(none.libraryList()->item(0)->flags() & Qt::ItemIsUserCheckable);
    EXPECT_TRUE(none.planFromApprovedLeaves().contains("No approved leaf"))
        << none.planFromApprovedLeaves().toStdString();
    EXPECT_EQ(none.plant(), nullptr);
  }
  {
    leafdig::db::Store store(db);
    for (std::int64_t id : {1, 2}) (void)acq::review(store, id, "approved", "cur", "");
  }
  leafdig::station::PlantView v;
  v.setDatabase(db);
  ASSERT_EQ(v.libraryList()->count(), 2);
  v.libraryList()->item(1)->setCheckState(Qt::Unchecked);
  ASSERT_EQ(v.planFromApprovedLeaves(), QString());
  ASSERT_EQ(v.plant()->leaves.size(), 1u) << "only the ticked leaf";
  EXPECT_EQ(v.plant()->leaves[0].source, "session 1");
  v.libraryList()->item(1)->setCheckState(Qt::Checked);
  ASSERT_EQ(v.planFromApprovedLeaves(), QString());
  EXPECT_EQ(v.plant()->leaves.size(), 2u);
  EXPECT_EQ(v.plant()->leaves[1].source, "session 2");
  std::filesystem::remove(db);
}

// The transmitter moved during the capture: the landmarks taken again are in the curator's
// list with their move, and correcting one places the points of that move again (each by its
// own correction, as from the CLI).
TEST(PlantView, ALandmarkTakenAgainAfterAMoveIsInTheCuratorsListAndItsCorrectionPlacesTheMoveAgain) {
  namespace acq = leafdig::acquisition;
  const std::string db =
      (QDir::tempPath() + "/leafdig-plant-moved-" + QString::number(::getpid()) + ".sqlite").toStdString();
  const std::int64_t id = captureSamplePlant(db, 8);
  ASSERT_FALSE(::testing::Test::HasFailure());
  leafdig::station::PlantView v;
  v.setDatabase(db);
  ASSERT_EQ(v.openCapturedPlant(id), QString());
  const auto items = v.correctableItems();
  const auto again = std::find_if(items.begin(), items.end(), [](const auto& i) {
    return i.item.plantWhat == acq::PlantWhat::LandmarkAgain && i.item.row == 2 && i.item.col == 1;
  });
  ASSERT_NE(again, items.end());
  EXPECT_TRUE(again->label.startsWith("Landmark 2 again · move 1 (")) << again->label.toStdString();
  const std::size_t before = leafdig::db::Store(db, true).events(id).size();
  acq::Correction c = again->item;
  (*c.positionMm)[2] += 0.6;
  c.who = "cur";
  c.reason = "pressed on the pot's rim";
  ASSERT_EQ(v.correctCaptured(c), QString());
  const auto events = leafdig::db::Store(db, true).events(id);
  EXPECT_GT(events.size(), before + 5);  // the landmark, then every point pressed after the move
  EXPECT_NE(events.back().payloadJson.find("placed again by its move's new fit (landmark_again 2 of move 1"),
            std::string::npos)
      << events.back().payloadJson;
  std::filesystem::remove(db);
}

TEST(PlantView, APlantCapturedWhereItStandsOpensAsMeasured) {
  namespace acq = leafdig::acquisition;
  const std::string db =
      (QDir::tempPath() + "/leafdig-plant-captured-" + QString::number(::getpid()) + ".sqlite").toStdString();
  const std::int64_t id = captureSamplePlant(db);
  ASSERT_FALSE(::testing::Test::HasFailure());
  leafdig::station::PlantView v;
  v.setDatabase(db);
  ASSERT_EQ(v.capturedList()->count(), 1);
  EXPECT_TRUE(v.capturedList()->itemText(0).contains("tobacco-p12")) << v.capturedList()->itemText(0).toStdString();
  EXPECT_EQ(v.capturedList()->itemData(0).toLongLong(), id);
  ASSERT_EQ(v.openCapturedPlant(id), QString());
  ASSERT_NE(v.plant(), nullptr);
  // Nodes 2 (full), 3 and 4 (quick) have leaves; the stem is as tall as the top node.
  ASSERT_EQ(v.plant()->leaves.size(), 3u);
  EXPECT_EQ(v.plant()->leaves[0].source, "digitized");
  EXPECT_FALSE(v.plant()->leaves[1].shapeDigitized);
  EXPECT_NEAR(v.plant()->stemHeightMm, 400.0, 2.0);
  EXPECT_TRUE(v.summaryText().contains("captured 2026-06-12")) << v.summaryText().toStdString();
  EXPECT_TRUE(v.summaryText().contains("built-in sample shape")) << v.summaryText().toStdString();
  EXPECT_FALSE(v.divergenceSlider()->isEnabled());  // measured, not planned
  // The divergences between successive leaves with points (nodes 2→3, 3→4), binned by 10°.
  {
    const auto store = leafdig::db::openEventStore(db, true);
    const acq::CapturedSurvey survey = acq::capturedSurvey(*store, id);
    std::vector<int> want(36, 0);
    for (const auto& l : survey.survey.leaves)
      if (l.divergenceDeg) ++want[static_cast<std::size_t>(*l.divergenceDeg / 10.0)];
    EXPECT_EQ(v.divergenceBins(), want);
    EXPECT_EQ(std::accumulate(want.begin(), want.end(), 0), 2);
  }
  EXPECT_FALSE(v.divergenceChart()->isHidden());
  EXPECT_TRUE(v.summaryText().contains("divergence: mean")) << v.summaryText().toStdString();
  // A curator corrects node 2's stem diameter; the plant is shown as corrected; a correction
  // without a reason or of a value out of range is refused in the engine's words.
  {
    const auto items = v.correctableItems();
    auto it = std::find_if(items.begin(), items.end(), [](const auto& i) {
      return i.item.plantWhat == acq::PlantWhat::Reading && i.item.row == 2;
    });
    ASSERT_NE(it, items.end());
    EXPECT_TRUE(it->label.startsWith("Node 2 · stem diameter")) << it->label.toStdString();
    EXPECT_TRUE(v.correctButton()->isEnabled());
    acq::Correction c = it->item;
    c.valueMm = 9.5;
    c.who = "cur";
    EXPECT_TRUE(v.correctCaptured(c).contains("reason")) << v.correctCaptured(c).toStdString();
    c.reason = "read in inches";
    acq::Correction huge = c;
    huge.valueMm = 1e6;
    EXPECT_TRUE(v.correctCaptured(huge).contains("outside this session's range"));
    ASSERT_EQ(v.correctCaptured(c), QString());
    EXPECT_TRUE(v.summaryText().contains("Corrected by cur: read in inches")) << v.summaryText().toStdString();
    const auto store = leafdig::db::openEventStore(db, true);
    EXPECT_DOUBLE_EQ(acq::capturedSurvey(*store, id).survey.nodes[1].diameterMm, 9.5);
    EXPECT_EQ(v.capturedStatus(), "complete");
    EXPECT_EQ(v.correctableItems().size(), items.size());
    // Node 2's full leaf: a marker corrected from the same list.
    const auto marker = std::find_if(items.begin(), items.end(), [](const auto& i) {
      return i.item.node == 2 && i.item.what == acq::What::Marker && i.item.row == 2 && i.item.col == 3;
    });
    ASSERT_NE(marker, items.end());
    EXPECT_TRUE(marker->label.startsWith("Node 2 · leaf marker · row 2 · point 3")) << marker->label.toStdString();
    acq::Correction m = marker->item;
    (*m.positionMm)[1] += 2.0;
    m.who = "cur";
    m.reason = "margin point on the wrong side";
    ASSERT_EQ(v.correctCaptured(m), QString());
    const auto again = leafdig::db::openEventStore(db, true);
    const auto leaf = std::get<leafdig::model::MarkerSet>(acq::capturedSurvey(*again, id).markers.nodes[1].leaf);
    EXPECT_DOUBLE_EQ(leaf.rows[1].pointsMm[2].y(), (*m.positionMm)[1]);
  }
  const QString out = QDir::tempPath() + "/leafdig-plant-captured-" + QString::number(::getpid()) + ".glb";
  EXPECT_EQ(v.exportTo(out), QString());
  EXPECT_GT(std::filesystem::file_size(out.toStdString()), 10000u);
  {
    // A captured plant's GLB is its session's: one node per MTG entity, the stem cut at the nodes.
    std::ifstream in(out.toStdString(), std::ios::binary);
    const std::string glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(glb.find("\"plant/stem/I3\""), std::string::npos);
    EXPECT_NE(glb.find("\"mtg_class\""), std::string::npos);
  }
  const QString mtg = QDir::tempPath() + "/leafdig-plant-captured-" + QString::number(::getpid()) + ".mtg";
  EXPECT_EQ(v.exportTo(mtg), QString());
  {
    std::ifstream in(mtg.toStdString());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("TopDia"), std::string::npos);
    EXPECT_NE(text.find("2026-06-12"), std::string::npos) << "the survey's day";
  }
  std::filesystem::remove(mtg.toStdString());
  std::filesystem::remove(out.toStdString());
  // A plan again: the sliders come back, the histogram goes.
  ASSERT_EQ(v.openPlan(QString::fromStdString(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/tobacco-p07.plant.json")),
            QString());
  EXPECT_TRUE(v.divergenceSlider()->isEnabled());
  EXPECT_TRUE(v.divergenceChart()->isHidden());
  EXPECT_TRUE(v.divergenceBins().empty());
  // A session that is not a plant is refused in words.
  EXPECT_TRUE(v.openCapturedPlant(id + 7).contains("no session")) << v.openCapturedPlant(id + 7).toStdString();
  std::filesystem::remove(db);
}

int main(int argc, char** argv) {
  // Widget tests need no display (also when CTest lists the tests at build time).
  if (!qEnvironmentVariableIsSet("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  QApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// The sample plant digitized in the station by the virtual technician through the simulated
// FASTRAK and caliper: the prompt and the tree follow the plant node by node, the leaf view
// opens while node 2's full leaf is taken, the 3-D plant ends as the captured plant's model;
// then "Review this plant" opens it in the Plant view, where a curator approves it.
// A station that simulates, at 50 times real time, on a database in `dir`, its settings there.
leafdig::station::StationOptions simulatingStation(const fs::path& dir) {
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.speed = 50;
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  return o;
}

const std::string kSamplePlant = std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json";

TEST(PlantCaptureView, APlantIsDigitizedInTheStationAndReviewedThere) {
  const leafdig::station::StationOptions o = simulatingStation(freshDir("plant-capture"));
  leafdig::station::StationWindow w(o);
  const std::string& sample = kSamplePlant;
  ASSERT_TRUE(w.startPlantCapture(sample)) << w.bannerText().toStdString();
  leafdig::station::PlantCaptureView* v = w.plantCapture();
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(w.tabs()->currentWidget(), v);
  // The field's line: not corrected, and no check in this file.
  EXPECT_EQ(v->fieldText(), "field: not corrected, and no check of the field today (leafdig field check)");
  // What the technician saw on the way: every prompt, the current entity of the tree at each.
  QStringList prompts, current;
  bool leafViewOpen = false;
  QObject::connect(v, &leafdig::station::PlantCaptureView::stepChanged, v, [&](const QString& prompt, bool) {
    prompts << prompt;
    const QTreeWidgetItem* c = v->tree()->currentItem();
    const QTreeWidgetItem* parent = c ? c->parent() : nullptr;
    current << (c ? (parent ? parent->text(0) + "/" : QString()) + c->text(0) : QString());
    leafViewOpen = leafViewOpen || v->leafPreview()->isVisibleTo(v);
  });
  for (int i = 0; i < 6000 && !v->complete(); ++i) QTest::qWait(20);
  ASSERT_TRUE(v->complete()) << v->bannerText().toStdString() << " / " << v->feedbackText().toStdString();
  EXPECT_EQ(v->bannerText(), "Plant complete");
  ASSERT_TRUE(prompts.contains("Node 3 · stem diameter with the caliper"));
  EXPECT_EQ(current.at(prompts.indexOf("Node 3 · stem diameter with the caliper")), "Node 3");
  const auto firstLeafPrompt = std::find_if(prompts.begin(), prompts.end(),
                                            [](const QString& p) { return p.startsWith("Node 2 · leaf · Row 3"); });
  ASSERT_NE(firstLeafPrompt, prompts.end());
  EXPECT_EQ(current.at(static_cast<int>(firstLeafPrompt - prompts.begin())), "Node 2/Leaf");
  EXPECT_TRUE(leafViewOpen) << "the leaf view opens while a full leaf is taken";
  EXPECT_GT(v->leafPreviewsShown(), 0);

  // The tree: landmarks, collar, five nodes with their diameters and leaves.
  ASSERT_EQ(v->tree()->topLevelItemCount(), 7);
  EXPECT_EQ(v->tree()->topLevelItem(1)->text(1), "Ø 21.5 mm");
  const QStringList leaves{"no leaf · dead", "full leaf, 10 rows · lower", "quick leaf, 3 of 3 points · lower",
                           "quick leaf, 3 of 3 points · lower", "no leaf"};
  for (int node = 1; node <= 5; ++node) {
    const QTreeWidgetItem* n = v->tree()->topLevelItem(node + 1);
    EXPECT_EQ(n->text(0), QString("Node %1").arg(node));
    EXPECT_TRUE(n->text(1).startsWith("Ø ")) << n->text(1).toStdString();
    ASSERT_EQ(n->childCount(), 1);
    EXPECT_EQ(n->child(0)->text(1), leaves[node - 1]) << "node " << node;
  }
  // The last preview reaches the view after the last decision: wait for it, then it is the
  // captured plant's model (stem, leaves 2, 3 and 4) in the plant frame.
  for (int i = 0; i < 500 && (!v->preview() || v->preview()->leaves < 3 || v->preview()->leafNode != 0); ++i)
    QTest::qWait(20);
  ASSERT_TRUE(v->preview());
  EXPECT_FALSE(v->leafPreview()->isVisibleTo(v)) << "the leaf view closes after the leaf";
  EXPECT_TRUE(v->preview()->inPlantFrame);
  EXPECT_EQ(v->preview()->leaves, 3);
  std::set<int> ranks;
  for (const auto& organ : v->preview()->mesh.organs) ranks.insert(organ.leafRank);
  EXPECT_EQ(ranks, (std::set<int>{0, 2, 3, 4}));
  EXPECT_TRUE(v->summaryText().contains("5 node(s)")) << v->summaryText().toStdString();
  {
    leafdig::db::Store store(o.db);
    EXPECT_EQ(store.session(v->sessionId())->status, "complete");
    EXPECT_EQ(store.session(v->sessionId())->kind, "plant");
  }

  // Review: the Plant view opens it as measured; a rejection needs words; approval is final.
  ASSERT_TRUE(v->reviewButton()->isEnabled());
  QTest::mouseClick(v->reviewButton(), Qt::LeftButton);
  ASSERT_EQ(w.tabs()->currentWidget(), w.plantView());
  ASSERT_NE(w.plantView()->plant(), nullptr);
  EXPECT_EQ(w.plantView()->plant()->leaves.size(), 3u);
  EXPECT_EQ(w.plantView()->capturedStatus(), "complete");
  EXPECT_TRUE(w.plantView()->approveButton()->isEnabled());
  EXPECT_TRUE(w.plantView()->rejectCaptured("cur", "").contains("say what is wrong"));
  EXPECT_EQ(w.plantView()->approveCaptured("cur"), QString());
  EXPECT_EQ(w.plantView()->capturedStatus(), "approved");
  EXPECT_FALSE(w.plantView()->approveButton()->isEnabled());
  EXPECT_TRUE(w.plantView()->approveCaptured("cur").contains("already approved"));
  leafdig::db::Store store(o.db);
  EXPECT_EQ(store.session(v->sessionId())->status, "approved");
  const auto events = store.events(v->sessionId());
  EXPECT_EQ(events.back().kind, "status");
  EXPECT_NE(events.back().payloadJson.find("\"cur\""), std::string::npos) << events.back().payloadJson;
  // Reopened by a curator with a reason: complete again, decided anew.
  EXPECT_TRUE(w.plantView()->reopenButton()->isEnabled());
  EXPECT_TRUE(w.plantView()->reopenCaptured("cur2", "").contains("say why the session is reopened"));
  EXPECT_EQ(w.plantView()->reopenCaptured("cur2", "node 2's leaf was skipped"), QString());
  EXPECT_EQ(w.plantView()->capturedStatus(), "complete");
  EXPECT_TRUE(w.plantView()->approveButton()->isEnabled());
  EXPECT_FALSE(w.plantView()->reopenButton()->isEnabled());
  EXPECT_EQ(store.session(v->sessionId())->status, "complete");
}

// A plant with a sucker digitized in the station by the branched protocol: the branch's nodes
// hang under the stem node that bears it in the tree, the Branch button is there for this
// protocol, and the preview draws the branch's tube beside the stem.
TEST(PlantCaptureView, ABranchedPlantHangsItsBranchUnderTheBearingNode) {
  const leafdig::station::StationOptions o = simulatingStation(freshDir("plant-branched"));
  leafdig::station::StationWindow w(o);
  const std::string data = std::string(LEAFDIG_SOURCE_DIR) + "/data";
  ASSERT_TRUE(
      w.startPlantCapture(data + "/plants/branched.plant-markers.json",
                          leafdig::model::readPlantProtocolFile(data + "/protocols/branched.plant-protocol.json")))
      << w.bannerText().toStdString();
  leafdig::station::PlantCaptureView* v = w.plantCapture();
  ASSERT_NE(v, nullptr);
  QStringList prompts;
  QObject::connect(v, &leafdig::station::PlantCaptureView::stepChanged, v,
                   [&](const QString& prompt, bool) { prompts << prompt; });
  for (int i = 0; i < 6000 && !v->complete(); ++i) QTest::qWait(20);
  ASSERT_TRUE(v->complete()) << v->bannerText().toStdString() << " / " << v->feedbackText().toStdString();
  EXPECT_TRUE(prompts.contains("Node 3 · branch diameter with the caliper")) << prompts.join("\n").toStdString();
  EXPECT_FALSE(v->branchButton()->isHidden());
  // Top level: landmarks, collar, nodes 1, 2, 5, 6, 7; nodes 3 and 4 under node 2.
  QStringList top;
  for (int k = 0; k < v->tree()->topLevelItemCount(); ++k) top << v->tree()->topLevelItem(k)->text(0);
  EXPECT_EQ(top, (QStringList{"Landmarks", "Collar", "Node 1", "Node 2", "Node 5", "Node 6", "Node 7"}));
  const QTreeWidgetItem* two = v->tree()->topLevelItem(3);
  QStringList under;
  for (int k = 0; k < two->childCount(); ++k) under << two->child(k)->text(0);
  EXPECT_EQ(under, (QStringList{"Leaf", "Node 3", "Node 4"}));
  for (int i = 0; i < 500 && (!v->preview() || v->preview()->leafNode != 0 || v->preview()->leaves < 5); ++i)
    QTest::qWait(20);
  ASSERT_TRUE(v->preview());
  std::set<std::string> axes;
  for (const auto& organ : v->preview()->mesh.organs)
    if (organ.leafRank == 0) axes.insert(organ.name);
  EXPECT_EQ(axes, (std::set<std::string>{"plant/stem", "plant/branch-3"}));
}

// The station's simulated plant on a turning pot (leafdig-station --simulate --plant-markers …
// --reference-receiver --pot-turn 30): the session keeps its reference receiver (a resume goes
// on in its frame), and the plant the virtual technician took is the file's, node by node,
// within the stylus' noise.
TEST(PlantCaptureView, APlantOnATurningPotUnderAReferenceReceiverIsTheFilesPlant) {
  leafdig::station::StationOptions o = simulatingStation(freshDir("plant-capture-pot"));
  o.referenceReceiver = true;
  o.potTurnDeg = 30;
  leafdig::station::StationWindow w(o);
  const std::string& sample = kSamplePlant;
  ASSERT_TRUE(w.startPlantCapture(sample)) << w.bannerText().toStdString();
  leafdig::station::PlantCaptureView* v = w.plantCapture();
  for (int i = 0; i < 6000 && !v->complete(); ++i) QTest::qWait(20);
  ASSERT_TRUE(v->complete()) << v->bannerText().toStdString() << " / " << v->feedbackText().toStdString();
  {
    leafdig::db::Store store(o.db, true);
    const auto info = store.session(v->sessionId());
    ASSERT_TRUE(info);
    EXPECT_EQ(acq::PlantCaptureSession::setupFromJson(info->settingsJson).digitizer, "fastrak:simulated,reference=2");
  }
  ASSERT_TRUE(v->engine());
  const m::PlantSurvey got = m::surveyPlant(v->engine()->captured("p"));
  const m::PlantSurvey want = m::surveyPlant(m::readPlantMarkersFile(sample));
  ASSERT_EQ(got.nodes.size(), want.nodes.size());
  for (std::size_t k = 0; k < got.nodes.size(); ++k)
    EXPECT_LT((got.nodes[k].pointMm - want.nodes[k].pointMm).norm(), 2.0) << "node " << k + 1;
}

TEST(PlantCaptureView, APlantFileThatDoesNotReadStartsNothingAndSaysWhy) {
  const fs::path dir = freshDir("plant-capture-bad");
  const fs::path bad = dir / "bad.plant-markers.json";
  std::ofstream(bad) << R"({"format": "leafdig.plant-markers/1", "units": "furlongs"})";
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(o);
  EXPECT_FALSE(w.startPlantCapture(bad.string()));
  EXPECT_TRUE(w.bannerText().contains("Cannot start the plant capture")) << w.bannerText().toStdString();
  EXPECT_TRUE(w.bannerText().contains("units")) << w.bannerText().toStdString();
  EXPECT_EQ(w.plantCapture()->sessionId(), 0);
  EXPECT_FALSE(w.plantCapture()->complete());
  leafdig::db::Store store(o.db);
  EXPECT_TRUE(store.sessions().empty());
}

// A person with the devices: a FASTRAK and a Sylvac on pseudo-terminals (the simulated rig, its
// ports named like any serial port), moved by the test's own hand. The stylus takes the
// landmarks, the Undo and End buttons do what a press cannot, the caliper reads the collar, the
// leaf controls set node 1's leaf; stopping keeps the session open.
// A technician's hands on a plant at the station: the simulated devices of a rig (their
// links in the test's folder), the station's options on a database there, the sample plant, and
// presses that wait until the station holds one more item.
struct HandsOnAPlant {
  HandsOnAPlant(const std::string& name, std::uint64_t seed) : dir(freshDir(name)), rig(simulation(dir, seed)) {
    o.audio = audio();
    o.db = (dir / "s.sqlite").string();
    o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  }
  static acq::SimulationOptions simulation(const fs::path& dir, std::uint64_t seed) {
    acq::SimulationOptions sim;
    sim.seed = seed;
    sim.mistakes = false;
    sim.stylusNoiseMm = 0.05;
    sim.linkDir = dir.string();
    return sim;
  }
  static bool waitFor(const std::function<bool()>& ok) {
    for (int i = 0; i < 1000 && !ok(); ++i) QTest::qWait(20);
    return ok();
  }
  // The plant session with the rig's devices.
  [[nodiscard]] acq::PlantSessionSetup setup(const std::string& plantId) const {
    acq::PlantSessionSetup s;
    s.plant = plantId;
    s.project = "p";
    s.operatorName = "ana";
    s.digitizer = rig.digitizerSpec();
    s.caliper = rig.caliperSpec();
    return s;
  }
  static std::size_t items(const leafdig::station::PlantCaptureView* v) {
    return v->engine() ? v->engine()->items().size() : 0U;
  }
  bool press(const leafdig::station::PlantCaptureView* v, const Eigen::Vector3d& p) {
    const std::size_t before = items(v);
    rig.hand().perform({{p.x(), p.y(), p.z()}, 0.35, 0.45, 0.6});
    return waitFor([&] { return items(v) > before; });
  }
  fs::path dir;
  acq::SimulatedRig rig;
  leafdig::station::StationOptions o;
  m::PlantMarkers plant =
      m::readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json");
};

TEST(PlantCaptureView, APersonDigitizesWithTheDevicesAndTheButtons) {
  HandsOnAPlant hands("plant-capture-devices", 5);
  acq::SimulatedRig& rig = hands.rig;
  leafdig::station::StationOptions& o = hands.o;
  o.setup.project = "p";
  o.setup.operatorName = "ana";
  o.setup.digitizer = rig.digitizerSpec();
  o.setup.caliper = rig.caliperSpec();
  {
    // An approved leaf of type "middle" (a simulated capture): the leaf controls offer its type.
    acq::RunRequest r;
    r.db = o.db;
    r.setup.project = "p";
    r.setup.plant = "P7";
    r.setup.leafPosition = 4;
    r.setup.leafType = "middle";
    r.setup.simulated = true;
    r.simulation.speed = 40;
    r.simulation.mistakes = false;
    r.preview = acq::PreviewDetail::None;
    std::int64_t approved = 0;
    {
      acq::CaptureRun run(r, {});
      run.start();
      run.wait();
      ASSERT_TRUE(run.shutdown("done").complete);
      approved = run.sessionId();
    }
    leafdig::db::Store store(o.db);
    (void)acq::review(store, approved, "approved", "cur", "");
  }
  leafdig::station::StationWindow w(o);
  ASSERT_TRUE(w.startPlantCaptureWithDevices(hands.setup("P-hands"))) << w.bannerText().toStdString();
  leafdig::station::PlantCaptureView* v = w.plantCapture();
  const auto waitFor = HandsOnAPlant::waitFor;
  EXPECT_TRUE(v->undoButton()->isVisibleTo(v));
  EXPECT_TRUE(waitFor([&] {
    return v->devicesText().contains("FASTRAK: streaming") && v->devicesText().contains("Sylvac: streaming");
  })) << v->devicesText().toStdString();
  const auto items = [&] { return HandsOnAPlant::items(v); };
  const m::PlantMarkers& plant = hands.plant;
  const auto press = [&](const Eigen::Vector3d& p) { return hands.press(v, p); };
  ASSERT_TRUE(press(plant.landmarksMm[0])) << v->feedbackText().toStdString();
  EXPECT_EQ(v->tree()->topLevelItem(0)->text(1), "1 taken");
  QTest::mouseClick(v->undoButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return items() == 0; })) << v->feedbackText().toStdString();
  for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(press(plant.landmarksMm[i])) << "landmark " << i + 1;
  QTest::mouseClick(v->endButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return v->bannerText().startsWith("Collar"); })) << v->bannerText().toStdString();
  ASSERT_TRUE(press(plant.collarMm));
  rig.caliper().hold(21.5);
  rig.caliperEmulator().pressData();
  ASSERT_TRUE(waitFor([&] { return v->tree()->topLevelItem(1)->text(1) == "Ø 21.5 mm"; }))
      << v->tree()->topLevelItem(1)->text(1).toStdString() << " / " << v->feedbackText().toStdString();
  // Retake: words that name no item are refused before anything is sent; an item not taken is
  // refused by the engine in words; landmark 2 is taken out (the banner says so) and pressed
  // again at its place. The Retake… dialog offers the tree's selected item in those words.
  EXPECT_TRUE(v->retakeButton()->isVisibleTo(v));
  EXPECT_TRUE(v->retake("stem 2").contains("a plant's item is landmark N")) << v->retake("stem 2").toStdString();
  EXPECT_EQ(v->retake("landmark 9"), "");
  ASSERT_TRUE(waitFor([&] { return v->feedbackText().contains("nothing was captured as landmark 9"); }))
      << v->feedbackText().toStdString();
  v->tree()->setCurrentItem(v->tree()->topLevelItem(0)->child(1));
  EXPECT_EQ(v->retakeSuggestion(), "landmark 2");
  EXPECT_EQ(v->retake(v->retakeSuggestion()), "");
  ASSERT_TRUE(waitFor([&] { return v->bannerText().startsWith("Retake · Landmark 2"); }))
      << v->bannerText().toStdString();
  ASSERT_TRUE(press(plant.landmarksMm[1])) << v->feedbackText().toStdString();
  ASSERT_TRUE(waitFor([&] { return !v->bannerText().startsWith("Retake"); })) << v->bannerText().toStdString();
  // The Accept key held down (a foot pedal) is the stylus button here too.
  QTest::keyPress(&w, Qt::Key_Return);
  EXPECT_TRUE(v->pedal());
  QTest::keyRelease(&w, Qt::Key_Return);
  EXPECT_FALSE(v->pedal());
  // Pause: the banner says so, a reading is logged as ignored and changes nothing; Resume.
  QTest::mouseClick(v->pauseButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return v->bannerText().startsWith("PAUSED"); })) << v->bannerText().toStdString();
  EXPECT_EQ(v->pauseButton()->text(), "Resume");
  const std::size_t held = items();
  rig.caliper().hold(3.3);
  rig.caliperEmulator().pressData();
  const auto logged = [&](const std::string& kind) {
    leafdig::db::Store reader(o.db, true);
    for (const auto& e : reader.events(v->sessionId()))
      if (e.kind == kind) return true;
    return false;
  };
  ASSERT_TRUE(waitFor([&] { return logged("ignored_reading"); }));
  EXPECT_EQ(items(), held);
  QTest::mouseClick(v->pauseButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return !v->bannerText().startsWith("PAUSED"); })) << v->bannerText().toStdString();
  EXPECT_EQ(v->pauseButton()->text(), "Pause");
  EXPECT_TRUE(v->feedbackText().contains("resumed")) << v->feedbackText().toStdString();
  // Node 1's leaf, before its first point: none, dead.
  EXPECT_EQ(v->setLeafButton()->text(), "Set node 1's leaf");
  EXPECT_NE(v->leafType()->findText("middle"), -1) << "the approved leaf's type is offered";
  v->leafKind()->setCurrentText("none");
  v->leafState()->setCurrentText("dead");
  QTest::mouseClick(v->setLeafButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return v->engine() && v->engine()->choiceFor(1).state == m::LeafState::Dead; }))
      << v->feedbackText().toStdString();
  EXPECT_EQ(v->engine()->choiceFor(1).kind, m::LeafKind::None);
  w.stopCapture();
  leafdig::db::Store store(o.db);
  const auto info = store.session(v->sessionId());
  ASSERT_TRUE(info);
  EXPECT_EQ(info->status, "open");
  EXPECT_EQ(info->plant, "P-hands");
  EXPECT_EQ(info->kind, "plant");
  std::vector<std::string> kinds;
  std::set<std::string> devicesLogged;
  for (const auto& e : store.events(v->sessionId())) {
    if (e.kind == "device") {  // each device's changes of state, as a leaf capture keeps them
      devicesLogged.insert(nlohmann::json::parse(e.payloadJson).at("device").get<std::string>());
      continue;
    }
    kinds.push_back(e.kind);
  }
  EXPECT_EQ(devicesLogged, (std::set<std::string>{"FASTRAK", "Sylvac"}));
  EXPECT_EQ(kinds, (std::vector<std::string>{"accepted", "undone", "accepted", "accepted", "accepted",
                                             "landmarks_ended", "accepted", "accepted", "rejected", "retake",
                                             "accepted", "paused", "ignored_reading", "resumed", "leaf_chosen"}));
}

// Moving the transmitter at the station (issue 29): after the collar the technician presses
// Move transmitter, moves it (the simulated transmitter goes 60 mm aside and turns 20°), takes
// three landmarks again and presses End; the tree's Transmitter line shows the new position's
// residual, and the next point lands in the first position's frame where the plant has it.
TEST(PlantCaptureView, ATechnicianMovesTheTransmitterWithTheButtonAndSeesTheResidual) {
  HandsOnAPlant hands("plant-capture-move", 6);
  acq::SimulatedRig& rig = hands.rig;
  leafdig::station::StationWindow w(hands.o);
  ASSERT_TRUE(w.startPlantCaptureWithDevices(hands.setup("P-moved"))) << w.bannerText().toStdString();
  leafdig::station::PlantCaptureView* v = w.plantCapture();
  const auto waitFor = HandsOnAPlant::waitFor;
  const m::PlantMarkers& plant = hands.plant;
  const auto press = [&](const Eigen::Vector3d& p) { return hands.press(v, p); };
  EXPECT_TRUE(v->moveButton()->isVisibleTo(v));
  for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(press(plant.landmarksMm[i])) << "landmark " << i + 1;
  QTest::mouseClick(v->endButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return v->bannerText().startsWith("Collar"); })) << v->bannerText().toStdString();
  ASSERT_TRUE(press(plant.collarMm));
  rig.caliper().hold(21.5);
  rig.caliperEmulator().pressData();
  ASSERT_TRUE(waitFor([&] { return v->bannerText().startsWith("Node 1"); })) << v->bannerText().toStdString();
  QTest::mouseClick(v->moveButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return v->bannerText().startsWith("Transmitter moved · landmark 1 again"); }))
      << v->bannerText().toStdString();
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.linear() =
      Eigen::AngleAxisd(20.0 * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  moved.translation() = Eigen::Vector3d(60, -40, 10);
  rig.moveTransmitter(moved);
  for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(press(plant.landmarksMm[i])) << "landmark " << i + 1 << " again";
  const auto transmitter = [&]() -> QTreeWidgetItem* {
    for (int k = 0; k < v->tree()->topLevelItemCount(); ++k)
      if (v->tree()->topLevelItem(k)->text(0) == "Transmitter") return v->tree()->topLevelItem(k);
    return nullptr;
  };
  ASSERT_TRUE(waitFor([&] { return transmitter() && transmitter()->childCount() == 1; }));
  EXPECT_EQ(transmitter()->child(0)->text(1), "moved: 3 landmarks taken again");
  QTest::mouseClick(v->endButton(), Qt::LeftButton);
  ASSERT_TRUE(waitFor([&] { return v->feedbackText().contains("fitted: RMS"); })) << v->feedbackText().toStdString();
  ASSERT_TRUE(transmitter());
  EXPECT_EQ(transmitter()->text(1), "position 2");
  ASSERT_EQ(transmitter()->childCount(), 1);
  EXPECT_EQ(transmitter()->child(0)->text(0), "Position 2");
  EXPECT_TRUE(transmitter()->child(0)->text(1).startsWith("RMS 0.")) << transmitter()->child(0)->text(1).toStdString();
  // Node 1's first point, pressed in the moved frame, is held in the first one.
  const Eigen::Vector3d node1 = plant.nodes.at(0).pointMm;
  ASSERT_TRUE(press(node1)) << v->feedbackText().toStdString();
  const acq::PlantItem& last = v->engine()->items().back();
  EXPECT_EQ(last.frame, 1);
  EXPECT_LT((Eigen::Vector3d(last.positionMm[0], last.positionMm[1], last.positionMm[2]) - node1).norm(), 1.0);
  w.stopCapture();
}

TEST(PlantCaptureView, ADevicesSpecThatDoesNotReadWritesNothing) {
  const fs::path dir = freshDir("plant-capture-bad-spec");
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.setup.digitizer = "wand:/dev/ttyS0";
  o.setup.caliper = "sylvac:/dev/ttyS1";
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  leafdig::station::StationWindow w(o);
  acq::PlantSessionSetup setup;
  setup.plant = "P";
  setup.digitizer = o.setup.digitizer;
  setup.caliper = o.setup.caliper;
  EXPECT_FALSE(w.startPlantCaptureWithDevices(setup));
  EXPECT_TRUE(w.bannerText().contains("wand")) << w.bannerText().toStdString();
  EXPECT_FALSE(fs::exists(o.db) && !leafdig::db::Store(o.db).sessions().empty());
}

// The plant set-up dialog: the plant and its devices chosen, or the problem in words before
// anything starts; the simulated pair digitizes a plant-markers file.
TEST(PlantSetupDialog, AChoiceIsValidatedAndNamesWhatIsMissing) {
  acq::PlantSessionSetup defaults;
  defaults.project = "tobacco-2026";
  defaults.operatorName = "ana";
  leafdig::db::SessionInfo earlier;
  earlier.kind = "plant";
  earlier.plant = "tobacco-p12";
  earlier.project = "tobacco-2026";
  const QString sample =
      QString::fromStdString(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json");
  leafdig::station::PlantSetupDialog d(defaults, {earlier}, leafdig::devices::Inventory{}, sample);
  EXPECT_NE(d.plant()->findText("tobacco-p12"), -1) << "a plant surveyed before is offered again";
  QString problem;
  d.plant()->setCurrentText("");
  EXPECT_FALSE(d.choice(&problem));
  EXPECT_TRUE(problem.contains("Name the plant")) << problem.toStdString();
  d.plant()->setCurrentText("tobacco-p12");
  // The simulated pair is listed first: a simulation of the sample plant.
  auto c = d.choice(&problem);
  ASSERT_TRUE(c) << problem.toStdString();
  EXPECT_TRUE(c->simulated);
  EXPECT_EQ(c->plantMarkers, sample.toStdString());
  EXPECT_EQ(c->setup.plant, "tobacco-p12");
  EXPECT_FALSE(c->referenceReceiver);
  d.referenceReceiver()->setChecked(true);
  c = d.choice(&problem);
  ASSERT_TRUE(c) << problem.toStdString();
  EXPECT_TRUE(c->simulated && c->referenceReceiver) << "the simulated pot with a reference receiver";
  d.referenceReceiver()->setChecked(false);
  d.date()->setText("2026-02-30");
  EXPECT_FALSE(d.choice(&problem));
  EXPECT_TRUE(problem.contains("YYYY-MM-DD")) << problem.toStdString();
  d.date()->setText("2026-07-01");
  // One real device and one simulated: refused; two real ones typed: their specs.
  d.digitizer()->setCurrentText("fastrak:/dev/ttyUSB0");
  EXPECT_FALSE(d.choice(&problem));
  EXPECT_TRUE(problem.contains("work together"))
      << problem.toStdString() << " (the leaf's dialog's words: both ask for devices through dialogs/device_fields)";
  d.caliper()->setCurrentText("sylvac:/dev/ttyUSB1");
  c = d.choice(&problem);
  ASSERT_TRUE(c) << problem.toStdString();
  EXPECT_FALSE(c->simulated);
  EXPECT_EQ(c->setup.digitizer, "fastrak:/dev/ttyUSB0");
  EXPECT_EQ(c->setup.caliper, "sylvac:/dev/ttyUSB1");
  ASSERT_TRUE(c->setup.date);
  EXPECT_EQ(leafdig::model::toIso(*c->setup.date), "2026-07-01");
  // A reference receiver on the pot: the digitizer's spec says so (once), and a simulation knows.
  d.referenceReceiver()->setChecked(true);
  c = d.choice(&problem);
  ASSERT_TRUE(c) << problem.toStdString();
  EXPECT_EQ(c->setup.digitizer, "fastrak:/dev/ttyUSB0,reference=2");
  d.digitizer()->setCurrentText("fastrak:/dev/ttyUSB0,reference=3");
  c = d.choice(&problem);
  ASSERT_TRUE(c) << problem.toStdString();
  EXPECT_EQ(c->setup.digitizer, "fastrak:/dev/ttyUSB0,reference=3") << "the receiver typed is kept";
  d.referenceReceiver()->setChecked(false);
  d.digitizer()->setCurrentText("wand:/dev/ttyUSB0");
  EXPECT_FALSE(d.choice(&problem));
  EXPECT_TRUE(problem.contains("wand")) << problem.toStdString();
  EXPECT_TRUE(problem.startsWith("Digitizer: ")) << problem.toStdString();
  // The plant's devices are rescanned as the leaf's are (the shared device fields).
  bool rescan = false;
  for (const auto* b : d.findChildren<QPushButton*>()) rescan = rescan || b->text() == "Rescan devices";
  EXPECT_TRUE(rescan) << "the plant's set-up offers 'Rescan devices' like the leaf's";
  d.protocol()->setText("/nonexistent.plant-protocol.json");
  d.digitizer()->setCurrentText("fastrak:/dev/ttyUSB0");
  EXPECT_FALSE(d.choice(&problem));
  EXPECT_TRUE(problem.contains("nonexistent")) << problem.toStdString();
}

// The correction dialog the leaf review and the Plant view share: the chosen item's stored
// position or value, edited, with the reason; nothing when cancelled.
TEST(CorrectionDialog, TheChosenItemIsEditedWithItsReasonAndCancelGivesNothing) {
  acq::Correction point;
  point.plantWhat = acq::PlantWhat::Landmark;
  point.row = 2;
  point.positionMm = acq::Vec3{1, 2, 3};
  acq::Correction reading;
  reading.plantWhat = acq::PlantWhat::Reading;
  reading.row = 3;
  reading.col = 1;
  reading.valueMm = 17.1;
  const std::vector<leafdig::station::CorrectionChoice> choices{{"Landmark 2", point}, {"Node 3 · stem", reading}};
  bool shown = false;
  QTimer::singleShot(0, [&] {
    auto* d = qobject_cast<QDialog*>(QApplication::activeModalWidget());
    ASSERT_NE(d, nullptr);
    shown = true;
    // The items as a tree: "Landmark 2" at the top, "Node 3 · stem" under Node 3.
    auto* which = d->findChild<QTreeWidget*>("correctionItems");
    ASSERT_NE(which, nullptr);
    ASSERT_EQ(which->topLevelItemCount(), 2);
    EXPECT_EQ(which->topLevelItem(0)->text(0), "Landmark 2");
    EXPECT_EQ(which->topLevelItem(1)->text(0), "Node 3");
    ASSERT_EQ(which->topLevelItem(1)->childCount(), 1);
    EXPECT_EQ(which->topLevelItem(1)->child(0)->text(0), "stem");
    const auto boxes = d->findChildren<QDoubleSpinBox*>();
    ASSERT_EQ(boxes.size(), 4);
    EXPECT_EQ(boxes[0]->value(), 1.0);  // the first item's stored position
    EXPECT_FALSE(boxes[3]->isEnabled());
    which->setCurrentItem(which->topLevelItem(1));  // a group: nothing chosen, nothing changes
    EXPECT_EQ(boxes[0]->value(), 1.0);
    which->setCurrentItem(which->topLevelItem(1)->child(0));  // the reading: its value, the position boxes off
    EXPECT_DOUBLE_EQ(boxes[3]->value(), 17.1);
    EXPECT_FALSE(boxes[0]->isEnabled());
    boxes[3]->setValue(16.4);
    d->findChild<QLineEdit*>()->setText("re-measured");
    d->accept();
  });
  const auto got = leafdig::station::askCorrection(nullptr, "Correct", choices, "diameter");
  ASSERT_TRUE(shown);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->plantWhat, acq::PlantWhat::Reading);
  EXPECT_EQ(got->row, 3);
  EXPECT_DOUBLE_EQ(*got->valueMm, 16.4);
  EXPECT_FALSE(got->positionMm);
  EXPECT_EQ(got->reason, "re-measured");
  QTimer::singleShot(0, [] { qobject_cast<QDialog*>(QApplication::activeModalWidget())->reject(); });
  EXPECT_FALSE(leafdig::station::askCorrection(nullptr, "Correct", choices, "diameter"));
  EXPECT_FALSE(leafdig::station::askCorrection(nullptr, "Correct", {}, "diameter"));  // nothing to offer
}

// Before a correction is written the station shows its effect (issue 49): the move, a warning
// above the station's limit, each measure before → after; the curator writes it or cancels.
TEST(CorrectionDialog, TheEffectIsShownAndTheCuratorWritesItOrNot) {
  acq::CorrectionEffect far;
  far.movedMm = 612.0;
  far.events = 1;
  far.changes.push_back({"blade area_mm2", 77656.0, 107010.0});
  const QString text = leafdig::station::effectText(far, 20.0);
  EXPECT_TRUE(text.contains("The point moves 612.0 mm. That is more than the 20.0 mm")) << text.toStdString();
  EXPECT_TRUE(text.contains("blade area_mm2: 77656.0 → 107010.0 (+37.8 %)")) << text.toStdString();
  acq::CorrectionEffect near = far;
  near.movedMm = 6.0;
  EXPECT_FALSE(leafdig::station::effectText(near, 20.0).contains("more than")) << "no warning under the limit";
  const auto answer = [](const QString& button, bool* warned) {
    QTimer::singleShot(0, [button, warned] {
      auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
      ASSERT_NE(box, nullptr);
      *warned = box->icon() == QMessageBox::Warning;
      for (QAbstractButton* b : box->buttons())
        if (b->text().contains(button)) b->click();
    });
  };
  bool warned = false;
  answer("Write", &warned);
  EXPECT_TRUE(leafdig::station::confirmCorrection(nullptr, far, 20.0));
  EXPECT_TRUE(warned) << "a far move asks with a warning";
  answer("Cancel", &warned);
  EXPECT_FALSE(leafdig::station::confirmCorrection(nullptr, near, 20.0));
  EXPECT_FALSE(warned);
}

// Issue 50: the Field tab. The technician checks the field with the sample jig in the simulated
// steel bench's field — every divot prompted and answered, the verdict and the error map shown,
// the check stored as `leafdig field check` stores it — calibrates the stylus' tip by pivoting it,
// and, with sentinel divots in the settings, a capture through the check takes three of its divots
// again first and begins only when they held; with the metal moved nearer it does not begin.
TEST(StationWindow, TheFieldTabChecksTheFieldDrawsItsMapAndTakesSentinelsBeforeACapture) {
  const fs::path dir = freshDir("field-tab");
  std::ofstream(dir / "station.ini") << "[field]\nsentinels=3\n";
  leafdig::station::StationOptions o;
  o.audio = audio();
  o.db = (dir / "s.sqlite").string();
  o.simulate = true;
  o.speed = 20;
  o.setup.project = "p";
  o.setup.plant = "pl";
  o.settingsFile = QString::fromStdString((dir / "station.ini").string());
  o.distortion =
      std::make_shared<const leafdig::devices::sim::FieldDistortion>(leafdig::devices::sim::readFieldDistortion(
          (fs::path(LEAFDIG_SOURCE_DIR) / "data/fields/steel-bench.field.json").string()));
  leafdig::station::StationWindow w(o);
  EXPECT_EQ(w.settings().sentinels, 3);
  leafdig::station::FieldView* field = w.fieldView();
  ASSERT_NE(field, nullptr);
  w.tabs()->setCurrentWidget(field);
  const auto waitFor = [&](const std::function<bool()>& ok, int seconds = 120) {
    for (int i = 0; i < seconds * 50 && !ok(); ++i) QTest::qWait(20);
    return ok();
  };
  field->checkButton()->click();  // as the technician presses it
  ASSERT_TRUE(field->running()) << field->resultText().toStdString();
  EXPECT_FALSE(field->checkButton()->isEnabled()) << "one run at a time";
  ASSERT_TRUE(waitFor([&] { return field->promptText().startsWith("touch divot "); }));
  ASSERT_TRUE(waitFor([&] { return !field->running(); })) << field->promptText().toStdString();
  const QStringList decisions = field->decisions();
  EXPECT_EQ(decisions.filter(QRegularExpression("^accepted: ")).size(), 22) << decisions.join("\n").toStdString();
  EXPECT_TRUE(decisions.last().startsWith("accepted: C4 taken (22 of 22)")) << decisions.last().toStdString();
  EXPECT_TRUE(field->promptText().contains("the correction brings it within tolerance"))
      << field->promptText().toStdString();
  EXPECT_TRUE(field->resultText().contains("verdict: correctable")) << field->resultText().toStdString();
  // The map: both views, an arrow per divot, the bench's worst beyond the tolerance in red.
  ASSERT_TRUE(field->map()->map());
  const auto& map = *field->map()->map();
  ASSERT_EQ(map.panels.size(), 2U);
  EXPECT_EQ(map.panels[0].arrows.size(), 22U);
  EXPECT_TRUE(std::any_of(map.panels[0].arrows.begin(), map.panels[0].arrows.end(),
                          [](const leafdig::model::FieldMapArrow& a) { return a.colour == "#d73027"; }));
  EXPECT_NE(map.summary.find(": correctable."), std::string::npos) << map.summary;
  {
    leafdig::db::Store store(o.db, true);
    const auto checks = acq::fieldCalibrations(store);
    ASSERT_EQ(checks.size(), 1U);
    EXPECT_EQ(checks[0].result.verdict, "correctable");
    EXPECT_EQ(checks[0].device, "fastrak:simulated");
  }
  if (const char* shots = std::getenv("LEAFDIG_TEST_SCREENSHOTS")) {
    w.resize(1400, 900);
    w.show();
    QTest::qWait(300);
    EXPECT_TRUE(w.grab().save(QString::fromStdString((fs::path(shots) / "field-check.png").string())));
  }
  // A capture through the check: the sentinel divots first, in the Field tab, then the leaf.
  w.options().fieldCalibration = "latest";
  ASSERT_TRUE(w.start()) << w.bannerText().toStdString();
  EXPECT_EQ(w.tabs()->currentWidget(), field);
  EXPECT_TRUE(w.bannerText().contains("touch the sentinel divots")) << w.bannerText().toStdString();
  ASSERT_TRUE(waitFor([&] { return w.sessionId() != 0; }))
      << w.bannerText().toStdString() << " / " << field->resultText().toStdString();
  EXPECT_TRUE(field->resultText().startsWith("3 sentinel divots of field check 1 taken again: the largest move "))
      << field->resultText().toStdString();
  EXPECT_EQ(field->decisions().filter(QRegularExpression("^accepted: ")).size(), 3);
  const std::int64_t id = w.sessionId();
  w.stopCapture();
  {
    leafdig::db::Store store(o.db, true);
    const auto applied = acq::fieldAppliedFromSettings(store.session(id)->settingsJson, "session");
    ASSERT_TRUE(applied && applied->sentinels);
    EXPECT_EQ(applied->id, 1);
    EXPECT_EQ(applied->sentinels->divots.size(), 3U);
    EXPECT_FALSE(applied->sentinels->moved());
  }
  // The metal moved nearer: the sentinels say so and no capture begins.
  leafdig::devices::sim::SteelBenchModel nearer;
  nearer.belowMm = 150;
  w.options().distortion =
      std::make_shared<const leafdig::devices::sim::FieldDistortion>(leafdig::devices::sim::steelBench(nearer));
  ASSERT_TRUE(w.start()) << w.bannerText().toStdString();
  ASSERT_TRUE(waitFor([&] { return !field->running(); }));
  QTest::qWait(100);
  EXPECT_TRUE(w.bannerText().contains("Not started: ")) << w.bannerText().toStdString();
  EXPECT_TRUE(w.bannerText().contains("the field moved since the check")) << w.bannerText().toStdString();
  EXPECT_EQ(field->promptText(), "The field moved since the check: check it again.");
  EXPECT_EQ(leafdig::db::Store(o.db, true).sessions().size(), 1U) << "no session was made";
  // The tip: a stylus whose sensor is 20 mm up its shaft, pivoted in a divot.
  ASSERT_TRUE(field->startTipCalibration({2, -1, 20}).isEmpty());
  ASSERT_TRUE(waitFor([&] { return !field->running(); })) << field->promptText().toStdString();
  EXPECT_TRUE(field->resultText().contains("verdict: pass")) << field->resultText().toStdString();
  EXPECT_EQ(field->promptText(), "The stylus tip is calibrated.");
  fs::remove_all(dir);
}
