// The station window's logic on Qt's offscreen platform: snapshots and feedback from a real
// capture session drive the banner, the step list, the device chips and the feedback line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <QApplication>
#include <QLabel>
#include <QListWidget>
#include <filesystem>

#include "leafdig/acquisition/session.hpp"
#include "leafdig/model/markers_json.hpp"
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

  leafdig::station::StationWindow w({});
  EXPECT_TRUE(w.windowTitle().startsWith("leafdig"));
  w.applySnapshot(session.snapshot());
  EXPECT_EQ(w.bannerText().toStdString(), "Tip: touch the leaf tip and press");
  std::int64_t t = 0;
  ASSERT_EQ(press(session, t, leaf.tipMm).at(0).kind, acq::Feedback::Kind::Accepted);
  for (int c = 0; c < 7; ++c) ASSERT_EQ(press(session, t, leaf.rows[0].pointsMm[static_cast<std::size_t>(c)]).at(0).kind, acq::Feedback::Kind::Accepted);
  ASSERT_EQ(press(session, t, leaf.rows[1].pointsMm[0]).at(0).kind, acq::Feedback::Kind::Accepted);
  w.applySnapshot(session.snapshot());
  EXPECT_EQ(w.bannerText().toStdString(), "Row 2 · point 2 of 7 · right lateral vein");
  const auto* steps = w.findChild<QListWidget*>();
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
  acq::Feedback device;
  device.kind = acq::Feedback::Kind::Device;
  device.text = "FASTRAK: connection lost — check the cable";
  w.applyFeedback(device);
  bool chip = false;
  for (const auto* l : w.findChildren<QLabel*>()) chip = chip || l->text().startsWith("FASTRAK: connection lost");
  EXPECT_TRUE(chip);
  // The preview holds the snapshot's partial model (midrib, row 1's laterals and contour).
  ASSERT_TRUE(w.lastSnapshot().has_value());
  EXPECT_EQ(w.lastSnapshot()->preview->model.veins.size(), 4u);
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
