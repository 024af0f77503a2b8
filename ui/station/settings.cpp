#include "settings.hpp"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QFont>
#include <QPalette>
#include <QSettings>
#include <QStandardPaths>
#include <QStyle>
#include <QStyleFactory>
#include <algorithm>

#include "leafdig/db/lab.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::station {

namespace {
constexpr NameTable<Action, 7> kActions{{{Action::Accept, "accept"},
                                         {Action::Undo, "undo"},
                                         {Action::EndRows, "end_rows"},
                                         {Action::Retake, "retake"},
                                         {Action::Pause, "pause"},
                                         {Action::Resume, "resume"},
                                         {Action::MoveTransmitter, "move_transmitter"}}};
}  // namespace

const char* toString(Action a) {
  return nameIn(kActions, a);
}

QString actionLabel(Action a) {
  switch (a) {
    case Action::Accept: return QObject::tr("Accept (held: stylus button / pedal)");
    case Action::Undo: return QObject::tr("Undo last point");
    case Action::EndRows: return QObject::tr("End rows");
    case Action::Retake: return QObject::tr("Retake selected step");
    case Action::Pause: return QObject::tr("Pause");
    case Action::Resume: return QObject::tr("Resume");
    case Action::MoveTransmitter: return QObject::tr("Move transmitter (then the board points again)");
  }
  return {};
}

StationSettings::StationSettings() {
  shortcuts[Action::Accept] = QKeySequence(Qt::Key_Return);
  shortcuts[Action::Undo] = QKeySequence(Qt::Key_Backspace);
  shortcuts[Action::EndRows] = QKeySequence(Qt::Key_E);
  shortcuts[Action::Retake] = QKeySequence(Qt::Key_R | Qt::ControlModifier);
  shortcuts[Action::Pause] = QKeySequence(Qt::Key_Escape);
  shortcuts[Action::Resume] = QKeySequence(Qt::Key_Space);
  shortcuts[Action::MoveTransmitter] = QKeySequence(Qt::Key_M | Qt::ControlModifier);
}

QString defaultSettingsFile() {
  return QStandardPaths::writableLocation(QStandardPaths::GenericConfigLocation) + "/leafdig/station.ini";
}

StationSettings StationSettings::load(const QString& file, QStringList* problems) {
  StationSettings s;
  QSettings q(file, QSettings::IniFormat);
  const auto note = [&](const QString& p) {
    if (problems) problems->push_back(p);
  };
  const auto number = [&](const char* key, double fallback, double lo, double hi) {
    if (!q.contains(key)) return fallback;
    bool ok = false;
    const double v = q.value(key).toDouble(&ok);
    if (!ok || v < lo || v > hi) {
      note(QObject::tr("%1 = %2 is not a number in [%3, %4]; using %5")
               .arg(key, q.value(key).toString())
               .arg(lo)
               .arg(hi)
               .arg(fallback));
      return fallback;
    }
    return v;
  };
  const auto word = [&](const char* key, const QString& fallback, const QStringList& allowed) {
    const QString v = q.value(key, fallback).toString();
    if (!allowed.contains(v)) {
      note(QObject::tr("%1 = %2 is not one of %3; using %4").arg(key, v, allowed.join(", "), fallback));
      return fallback;
    }
    return v;
  };
  s.units = word("display/units", s.units, {"mm", "in"});
  s.theme = word("display/theme", s.theme, {"light", "dark"});
  s.fontScale = number("display/font_scale", s.fontScale, 0.8, 2.5);
  s.sounds = q.value("sound/enabled", s.sounds).toBool();
  s.volume = number("sound/volume", s.volume, 0.0, 1.0);
  for (auto& [action, key] : s.shortcuts) {
    const QString name = QString("shortcuts/") + toString(action);
    if (!q.contains(name)) continue;
    const QKeySequence k(q.value(name).toString(), QKeySequence::PortableText);
    if (k.isEmpty() && !q.value(name).toString().isEmpty())
      note(QObject::tr("%1: unknown key '%2'").arg(name, q.value(name).toString()));
    else
      key = k;
  }
  auto& e = s.engine;
  e.stillWindowNs = static_cast<std::int64_t>(
      number("capture/still_window_ms", static_cast<double>(e.stillWindowNs) / 1e6, 50, 2000) * 1e6);
  e.stillToleranceMm = number("capture/still_tolerance_mm", e.stillToleranceMm, 0.1, 10);
  e.spacingTolerance = number("capture/spacing_tolerance", e.spacingTolerance, 0.1, 2.0);
  e.midribToleranceMm = number("capture/midrib_tolerance_mm", e.midribToleranceMm, 1, 100);
  e.relocationToleranceMm = number("capture/relocation_tolerance_mm", e.relocationToleranceMm, 0.1, 10);
  e.minThicknessMm = number("capture/min_thickness_mm", e.minThicknessMm, 0.001, 5);
  e.maxThicknessMm = number("capture/max_thickness_mm", e.maxThicknessMm, 1, 100);
  s.exportDir = q.value("export/dir", QDir::homePath() + "/leafdig-exports").toString();
  s.labUrl = q.value("lab/url", QString()).toString().trimmed();
  if (!s.labUrl.isEmpty() && !s.labUrl.startsWith("postgresql://") && !s.labUrl.startsWith("postgres://")) {
    note(QObject::tr("lab/url = %1 is not a postgresql:// URL; no lab server")
             .arg(QString::fromStdString(db::redactUrl(s.labUrl.toStdString()))));
    s.labUrl.clear();
  }
  if (!s.labUrl.isEmpty()) {
    const QString bare = labUrlWithoutPassword(s.labUrl);
    if (bare != s.labUrl)
      note(
          QObject::tr("lab/url holds a password, which the station never stores: it is not used (put it in "
                      "~/.pgpass, mode 0600 — docs/lab.md)"));
    s.labUrl = bare;
  }
  s.labSyncMinutes = static_cast<int>(number("lab/sync_minutes", s.labSyncMinutes, 0, 1440));
  s.confirmMoveAboveMm = number("review/confirm_move_above_mm", s.confirmMoveAboveMm, 0.1, 10000.0);
  s.fieldCheckMaxAgeHours =
      number("field/max_check_age_hours", s.fieldCheckMaxAgeHours, 1.0, acquisition::kFieldCheckMaxAgeLimitHours);
  if (q.contains("field/sentinels")) {
    bool ok = false;
    const int n = q.value("field/sentinels").toString().toInt(&ok);
    if (ok && (n == 0 || (n >= acquisition::kMinSentinels && n <= acquisition::kMaxSentinels)))
      s.sentinels = n;
    else
      note(QObject::tr("field/sentinels = %1 is not 0, 3, 4 or 5; no sentinel divots")
               .arg(q.value("field/sentinels").toString()));
  }
  return s;
}

void StationSettings::save(const QString& file) const {
  QDir().mkpath(QFileInfo(file).absolutePath());
  QSettings q(file, QSettings::IniFormat);
  q.setValue("display/units", units);
  q.setValue("display/theme", theme);
  q.setValue("display/font_scale", fontScale);
  q.setValue("sound/enabled", sounds);
  q.setValue("sound/volume", volume);
  for (const auto& [action, key] : shortcuts)
    q.setValue(QString("shortcuts/") + toString(action), key.toString(QKeySequence::PortableText));
  q.setValue("capture/still_window_ms", static_cast<double>(engine.stillWindowNs) / 1e6);
  q.setValue("capture/still_tolerance_mm", engine.stillToleranceMm);
  q.setValue("capture/spacing_tolerance", engine.spacingTolerance);
  q.setValue("capture/midrib_tolerance_mm", engine.midribToleranceMm);
  q.setValue("capture/relocation_tolerance_mm", engine.relocationToleranceMm);
  q.setValue("capture/min_thickness_mm", engine.minThicknessMm);
  q.setValue("capture/max_thickness_mm", engine.maxThicknessMm);
  q.setValue("export/dir", exportDir);
  q.setValue("lab/url", labUrlWithoutPassword(labUrl));
  q.setValue("lab/sync_minutes", labSyncMinutes);
  q.setValue("review/confirm_move_above_mm", confirmMoveAboveMm);
  q.setValue("field/max_check_age_hours", fieldCheckMaxAgeHours);
  q.setValue("field/sentinels", sentinels);
  q.sync();
  // Only its owner reads the station's settings (they name the lab server and its login).
  QFile::setPermissions(file, QFileDevice::ReadOwner | QFileDevice::WriteOwner);
}

QString labUrlWithoutPassword(const QString& url) {
  if (url.isEmpty()) return url;
  const auto bare = db::urlWithoutSecrets(url.toStdString());
  return bare ? QString::fromStdString(*bare) : QString();  // unreadable: it may hold one, so not kept
}

QString StationSettings::number(double mm, int decimalsMm) const {
  if (units == "in") return QString::number(mm / 25.4, 'f', decimalsMm + 1);
  return QString::number(mm, 'f', decimalsMm);
}

QString StationSettings::length(double mm, int decimalsMm) const {
  return number(mm, decimalsMm) + " " + units;
}

void applyTheme(QApplication& app, const StationSettings& s) {
  app.setStyle(QStyleFactory::create("Fusion"));
  QPalette p;
  if (s.theme == "dark") {
    p.setColor(QPalette::Window, QColor(37, 40, 45));
    p.setColor(QPalette::WindowText, QColor(230, 232, 235));
    p.setColor(QPalette::Base, QColor(28, 30, 34));
    p.setColor(QPalette::AlternateBase, QColor(45, 48, 54));
    p.setColor(QPalette::Text, QColor(230, 232, 235));
    p.setColor(QPalette::Button, QColor(50, 54, 60));
    p.setColor(QPalette::ButtonText, QColor(230, 232, 235));
    p.setColor(QPalette::Highlight, QColor(64, 140, 220));
    p.setColor(QPalette::HighlightedText, Qt::white);
    p.setColor(QPalette::ToolTipBase, QColor(50, 54, 60));
    p.setColor(QPalette::ToolTipText, QColor(230, 232, 235));
    p.setColor(QPalette::PlaceholderText, QColor(150, 150, 150));
  } else {
    p = app.style()->standardPalette();
  }
  app.setPalette(p);
  QFont f = app.font();
  static const double base = f.pointSizeF() > 0 ? f.pointSizeF() : 10.0;
  f.setPointSizeF(base * s.fontScale);
  app.setFont(f);
}

}  // namespace leafdig::station
