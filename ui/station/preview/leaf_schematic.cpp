#include "preview/leaf_schematic.hpp"

#include <QPainter>
#include <QPainterPath>
#include <cmath>

namespace leafdig::station {
namespace acq = leafdig::acquisition;

LeafSchematic::LeafSchematic(QWidget* parent) : QWidget(parent) {
  setMinimumSize(160, 220);
  setSizePolicy(QSizePolicy::Preferred, QSizePolicy::Expanding);
  setAccessibleName(tr("Where the next marker is"));
}

void LeafSchematic::show(const acq::Snapshot& s) {
  snapshot_ = s;
  has_ = true;
  int seen = 0;
  for (const auto& i : s.items) seen = std::max(seen, i.row);
  rows_ = std::max({4, seen + (s.rowsEnded || s.complete ? 0 : 1), s.step.row});
  update();
}

QPointF LeafSchematic::at(int row, int col) const {
  // Leaf outline: half-width w(u) = sin(pi u)^0.8 over u in [0, 1] from the tip to the base.
  const double top = 24, bottom = height() - 30.0;
  // While rows are being taken there is room for the next below the last; once they are
  // ended the last row sits at the base, where the protocol puts it.
  const bool ended = has_ && (snapshot_.rowsEnded || snapshot_.complete);
  const double u = static_cast<double>(row) / (ended ? rows_ : rows_ + 1);
  const double y = top + u * (bottom - top);
  const double half = 0.42 * width() * std::pow(std::sin(M_PI * std::min(u, 0.93)), 0.8);
  // col 1 = right margin … 4 = midrib … 7 = left margin (seen from the top: right is right).
  const double x = width() / 2.0 + half * (4 - col) / 3.0;
  return {x, y};
}

QPointF LeafSchematic::targetPosition() const {
  if (!has_) return {};
  const acq::Step& step = snapshot_.step;
  switch (step.what) {
    case acq::What::Tip: return at(0, 4);
    case acq::What::Marker: return at(step.row, step.col);
    case acq::What::MidribThickness:
    case acq::What::VeinOriginThickness:
    case acq::What::PointThickness: return at(step.row, step.col > 0 ? step.col : 4);
    case acq::What::EdgeThickness: return at(std::max(1, rows_ / 2), acq::kMarkersPerRow);
    default: return {};
  }
}

void LeafSchematic::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const QColor leafFill =
      palette().color(QPalette::Base).lightness() < 100 ? QColor(40, 80, 45) : QColor(214, 236, 206);
  const QColor ink = palette().color(QPalette::WindowText);
  // Outline.
  QPainterPath outline;
  outline.moveTo(at(0, 4));
  for (int r = 1; r <= rows_; ++r) outline.lineTo(at(r, acq::kMarkersPerRow));
  outline.lineTo(QPointF(width() / 2.0, height() - 30.0));
  for (int r = rows_; r >= 1; --r) outline.lineTo(at(r, 1));
  outline.closeSubpath();
  p.setPen(QPen(QColor(60, 120, 60), 2));
  p.setBrush(leafFill);
  p.drawPath(outline);
  // Midrib and petiole.
  p.setPen(QPen(QColor(120, 100, 50), 3));
  p.drawLine(at(0, 4), QPointF(width() / 2.0, height() - 8.0));
  p.setPen(QPen(QColor(120, 100, 50), 1.5));
  for (int r = 1; r <= rows_; ++r) {
    p.drawLine(at(r, 4), at(r - 1, 2) * 0.5 + at(r, 2) * 0.5);
    p.drawLine(at(r, 4), at(r - 1, 6) * 0.5 + at(r, 6) * 0.5);
  }
  // The leaf base, where the blade meets the petiole: the protocol's last row goes there.
  {
    const QPointF base(width() / 2.0, height() - 30.0);
    p.setPen(QPen(QColor(120, 100, 50), 1.5, Qt::DashLine));
    p.drawLine(base - QPointF(0.18 * width(), 0), base + QPointF(0.18 * width(), 0));
    QFont small = font();
    small.setPointSizeF(small.pointSizeF() * 0.85);
    p.setFont(small);
    p.setPen(palette().color(QPalette::WindowText));
    p.drawText(QRectF(base.x() + 6, base.y() + 2, width() / 2.0 - 8, 20), Qt::AlignLeft | Qt::AlignTop,
               tr("base: last row"));
    p.setFont(font());
  }
  target_ = {};
  if (!has_) return;
  const acq::Step& step = snapshot_.step;
  // Points: captured filled, the rest hollow.
  const auto done = [&](acq::What w, int row, int col) {
    return acq::findItem(snapshot_.items, w, row, col) != nullptr;
  };
  const auto dot = [&](const QPointF& c, bool filled) {
    p.setPen(QPen(filled ? QColor(27, 94, 32) : QColor(130, 130, 130), 1.5));
    p.setBrush(filled ? QColor(46, 125, 50) : Qt::NoBrush);
    p.drawEllipse(c, 4.5, 4.5);
  };
  dot(at(0, 4), done(acq::What::Tip, 0, 0));
  for (int r = 1; r <= rows_; ++r)
    for (int c = 1; c <= acq::kMarkersPerRow; ++c) dot(at(r, c), done(acq::What::Marker, r, c));
  // The target.
  target_ = targetPosition();
  QString label;
  switch (step.what) {
    case acq::What::Tip: label = tr("tip"); break;
    case acq::What::Marker: label = tr("row %1 · %2").arg(step.row).arg(step.col); break;
    case acq::What::MidribThickness:
    case acq::What::VeinOriginThickness:
    case acq::What::PointThickness: label = tr("back · row %1").arg(step.row); break;
    case acq::What::EdgeThickness: label = tr("margin (d)"); break;
    default: break;
  }
  if (target_.isNull()) return;
  const bool thickness = !acq::isStylusItem(step.what);
  const QColor hot = thickness ? QColor(21, 101, 192) : QColor(229, 57, 53);
  p.setPen(QPen(hot, 3));
  p.setBrush(Qt::NoBrush);
  p.drawEllipse(target_, 11, 11);
  p.setBrush(hot);
  p.drawEllipse(target_, 5, 5);
  QFont f = font();
  f.setBold(true);
  p.setFont(f);
  p.setPen(ink);
  const QRectF box(target_.x() - 80, target_.y() + 12, 160, 22);
  p.drawText(box, Qt::AlignHCenter | Qt::AlignTop, label);
}

}  // namespace leafdig::station
