// The station's settings: what an operator or curator sets once and keeps (QSettings, INI
// file under ~/.config/leafdig/station.ini unless --settings names another). Engine
// tolerances apply to sessions created afterwards; a session keeps the settings it was
// captured with (they are in its row).
#pragma once

#include <QApplication>
#include <QKeySequence>
#include <QString>
#include <map>

#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/acquisition/review/correction.hpp"

namespace leafdig::station {

// The operator commands that have shortcuts (a USB foot pedal types one of these keys).
enum class Action { Accept, Undo, EndRows, Retake, Pause, Resume, MoveTransmitter };
[[nodiscard]] const char* toString(Action a);  // "undo", "end_rows", …
[[nodiscard]] QString actionLabel(Action a);   // "Undo last point", …

struct StationSettings {
  QString units = "mm";                      // shown: "mm" or "in" (stored values are always mm)
  QString theme = "light";                   // "light" or "dark" (Qt 6.4 cannot ask the system)
  double fontScale = 1.25;                   // arm's-length reading: 1.0 .. 2.5
  bool sounds = true;                        // accept, reject, step done, device error
  double volume = 0.8;                       // 0 .. 1
  std::map<Action, QKeySequence> shortcuts;  // filled with the defaults below
  acquisition::Settings engine;              // tolerances and stillness for new sessions
  QString exportDir;                         // last export destination
  // The lab's PostgreSQL server this station syncs to (docs/lab.md): a postgresql:// URL
  // without its password (libpq reads ~/.pgpass); empty: no lab server. Every
  // `labSyncMinutes` the station pushes its sessions and pulls decisions (0: only by hand).
  QString labUrl;
  int labSyncMinutes = 0;
  // A curator's correction that would move a point further than this (mm) is asked about with a
  // warning before it is written (the CLI's --confirm-above; every correction shows its effect).
  double confirmMoveAboveMm = acquisition::kConfirmMoveAboveMm;
  // How old a field check may be before the capture says the field was not checked (hours; the
  // CLI's --field-check-max-age-hours reads the same key, field/max_check_age_hours).
  double fieldCheckMaxAgeHours = acquisition::kFieldCheckMaxAgeHours;
  // How many of the field check's divots a capture through it takes again before its first leaf
  // (0: none, else 3 to 5; the CLI's --sentinels reads the same key, field/sentinels).
  int sentinels = 0;

  StationSettings();
  // Reads from the INI file (missing keys keep their defaults; out-of-range values are
  // clamped and reported in `problems`). Writes back with save().
  static StationSettings load(const QString& file, QStringList* problems = nullptr);
  void save(const QString& file) const;
  // "12.34 mm" or "0.486 in".
  [[nodiscard]] QString length(double mm, int decimalsMm = 2) const;
  // The number alone, in the units shown (a column header carries the unit).
  [[nodiscard]] QString number(double mm, int decimalsMm = 2) const;
};

[[nodiscard]] QString defaultSettingsFile();
// A lab URL as the station keeps it: without a password or sslpassword (those live in
// ~/.pgpass); empty when libpq cannot read it (it may hold one).
[[nodiscard]] QString labUrlWithoutPassword(const QString& url);
// Palette, font size and style for the theme; call before and after windows exist.
void applyTheme(QApplication& app, const StationSettings& s);

}  // namespace leafdig::station
