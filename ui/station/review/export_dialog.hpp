// Export: formats, frame, resolution, destination, over one session or a selection, with a
// progress dialog that can be cancelled between files. exportBatch() is the work without
// the dialog (the tests drive it; the dialog runs it with a QProgressDialog).
#pragma once

#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QLineEdit>
#include <functional>
#include <map>

#include "leafdig/acquisition/review/leaf_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "preview/mesh_choice.hpp"
#include "settings.hpp"

namespace leafdig::station {

struct BatchResult {
  std::vector<std::string> written;
  std::vector<std::pair<std::int64_t, std::string>> failed;  // session, why
  // Exported, but no curator approved them (issue 49): session, its status.
  std::vector<std::pair<std::int64_t, std::string>> unapproved;
  bool cancelled = false;
};
// The words the dialog adds for files of sessions no curator approved (empty when all were):
// "Not approved by a curator: session 3 (complete), … — their numbers are as captured, unchecked."
[[nodiscard]] QString unapprovedWarning(const BatchResult& result);
// progress(done, total, what) returns false to cancel; the session being written finishes.
BatchResult exportBatch(const std::string& dbPath, const std::vector<std::int64_t>& sessions,
                        const acquisition::ExportRequest& request,
                        const std::function<bool(int, int, const QString&)>& progress);

class ExportDialog : public QDialog {
  Q_OBJECT

 public:
  explicit ExportDialog(StationSettings& settings, QWidget* parent = nullptr);
  void setSessions(const std::vector<std::int64_t>& ids);
  [[nodiscard]] acquisition::ExportRequest request() const;
  // Runs the batch with a cancellable progress dialog and reports what happened.
  BatchResult run(const std::string& dbPath);

  QLineEdit* destination() const { return dir_; }
  QCheckBox* format(const std::string& f) const { return formats_.at(f); }
  QComboBox* frame() const { return frame_; }
  QComboBox* resolution() const { return resolution_; }
  MeshChoice* mesh() const { return mesh_; }

 private:
  StationSettings& settings_;
  std::vector<std::int64_t> sessions_;
  std::map<std::string, QCheckBox*> formats_;
  QComboBox *frame_, *resolution_;
  MeshChoice* mesh_;
  QLineEdit* dir_;
  QLineEdit* ids_;
};

}  // namespace leafdig::station
