// The curators' view: browse sessions (project, plant, status, operator, date), open one,
// see its markers in a table linked to the 3D view (select in one, highlight in the other),
// thickness profiles along the midrib and the veins (Qt Charts) with flagged readings
// marked, the model's metrics and the area constraint, the hash-chain status; correct an
// item with a reason (a `corrected` event), approve or reject, export, and replay the
// session event by event through the same engine. A purple banner: never mistaken for a
// live capture.
#pragma once

#include <QComboBox>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QSlider>
#include <QTableWidget>
#include <QWidget>
#include <memory>
#include <optional>
#include <utility>

#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "preview/preview_widget.hpp"
#include "settings.hpp"

class QChartView;
class QPushButton;

namespace leafdig::station {

class ReviewView : public QWidget {
  Q_OBJECT

 public:
  explicit ReviewView(const StationSettings& settings, QWidget* parent = nullptr);
  ~ReviewView() override;
  void setDatabase(const std::string& path);
  void setSettings(const StationSettings& s);
  void refreshSessions();
  // Opens a session (replayed up to `upToSeq`, 0: all). False when it cannot be opened
  // (the banner says why).
  bool openSession(std::int64_t id, std::int64_t upToSeq = 0);
  void replayTo(std::int64_t seq);
  void selectItem(const acquisition::Item& item);  // table row + 3D highlight
  // Actions (the buttons ask for the reason / value and call these). Errors come back as
  // text and are shown in the banner.
  QString correct(const acquisition::Correction& c);
  QString approve(const QString& who);
  QString reject(const QString& who, const QString& why);
  QString reopen(const QString& who, const QString& why);  // an approved or rejected session, complete again

  [[nodiscard]] QTableWidget* sessionsTable() const { return sessions_; }
  [[nodiscard]] QTableWidget* markersTable() const { return markers_; }
  [[nodiscard]] QListWidget* flagsList() const { return flags_; }
  [[nodiscard]] PreviewWidget* preview() const { return preview_; }
  [[nodiscard]] QChartView* chart() const { return chart_; }
  [[nodiscard]] QString bannerText() const { return banner_->text(); }
  [[nodiscard]] QString metricsText() const { return metrics_->text(); }
  [[nodiscard]] QComboBox* statusFilter() const { return status_; }
  [[nodiscard]] QLineEdit* curator() const { return curator_; }
  [[nodiscard]] QSlider* replaySlider() const { return slider_; }
  [[nodiscard]] const std::optional<acquisition::ReviewedSession>& current() const { return current_; }
  // Correct, Approve and Reject: enabled only for a complete session shown whole (issue 49).
  [[nodiscard]] bool decisionsEnabled() const;
  [[nodiscard]] bool reopenEnabled() const;  // Reopen…: an approved or rejected session shown whole
  // What this view leaves to the Plant tab ("2 plant sessions: review them in the Plant tab").
  [[nodiscard]] QString plantNote() const { return plantNote_->text(); }

 private:
  // Approve or reject the open session (`status`), reporting `failed` in the banner.
  QString decide(const char* status, const QString& failed, const QString& who, const QString& why);
  void fill();
  void fillChart(const std::vector<acquisition::ReviewFlag>& flags);
  void correctSelected();
  void applyFilters();
  std::optional<acquisition::Item> itemOfRow(int row) const;

  StationSettings settings_;
  std::string dbPath_;
  std::unique_ptr<db::EventStore> store_;  // the station's file, or the lab server
  std::optional<acquisition::ReviewedSession> current_;
  std::vector<db::SessionInfo> all_;
  std::pair<std::int64_t, std::int64_t> chainOf_{0, -1};  // (session, head seq) chain_ is for
  db::ChainReport chain_;
  QLabel *banner_, *metrics_, *replayLabel_, *plantNote_;
  QPushButton *correctB_ = nullptr, *approveB_ = nullptr, *rejectB_ = nullptr, *reopenB_ = nullptr;
  QComboBox *project_, *plant_, *status_, *operator_;
  QLineEdit *date_, *curator_;
  QTableWidget *sessions_, *markers_;
  QListWidget* flags_;
  PreviewWidget* preview_;
  QChartView* chart_;
  QSlider* slider_;
  bool filling_ = false;
};

}  // namespace leafdig::station
