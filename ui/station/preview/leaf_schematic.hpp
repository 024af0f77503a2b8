// A schematic leaf (tip up, seen from the top side) with the marker grid of docs/method.md §1: done
// points filled, the next marker ringed and labelled, thickness steps shown at the midrib /
// vein origin / margin on the back side. The operator looks here, not at the 3D view, to
// find where the stylus goes next.
#pragma once

#include <QWidget>

#include "leafdig/acquisition/session/session.hpp"

namespace leafdig::station {

class LeafSchematic : public QWidget {
  Q_OBJECT

 public:
  explicit LeafSchematic(QWidget* parent = nullptr);
  void show(const acquisition::Snapshot& s);
  // Where the highlighted target is drawn (widget coordinates), for tests; null when none.
  [[nodiscard]] QPointF targetPosition() const;
  [[nodiscard]] int rowsDrawn() const { return rows_; }
  [[nodiscard]] QSize sizeHint() const override { return {220, 320}; }

 protected:
  void paintEvent(QPaintEvent* e) override;

 private:
  [[nodiscard]] QPointF at(int row, int col) const;  // row 0 = tip
  acquisition::Snapshot snapshot_;
  bool has_ = false;
  int rows_ = 4;
  QPointF target_;
};

}  // namespace leafdig::station
