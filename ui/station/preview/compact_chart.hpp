// The station's small charts (review's thickness plot, the Plant view's divergences): a title
// in a slightly smaller font, thin margins, square corners; then two value axes attached to
// every series; then the chart put in its view (the view's old chart deleted).
#pragma once

#include <QChart>
#include <QChartView>
#include <QValueAxis>

namespace leafdig::station {

// A new chart titled `title`; `small` receives the title's font, for labels and legends.
inline QChart* compactChart(const QString& title, QFont& small) {
  auto* chart = new QChart;
  chart->setTitle(title);
  small = chart->titleFont();
  small.setPointSizeF(small.pointSizeF() * 0.9);
  chart->setTitleFont(small);
  chart->setMargins(QMargins(2, 2, 2, 2));
  chart->setBackgroundRoundness(0);
  return chart;
}

// Adds `x` (bottom) and `y` (left), attaches every series to both, and shows the chart.
inline void showChart(QChartView* view, QChart* chart, QValueAxis* x, QValueAxis* y) {
  chart->addAxis(x, Qt::AlignBottom);
  chart->addAxis(y, Qt::AlignLeft);
  for (auto* series : chart->series()) {
    series->attachAxis(x);
    series->attachAxis(y);
  }
  QChart* old = view->chart();
  view->setChart(chart);
  delete old;
}

}  // namespace leafdig::station
