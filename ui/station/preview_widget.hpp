// The live 3D preview: the snapshot's vein tubes and blade, the markers, the last accepted
// point highlighted; orbit (left drag), pan (right drag), zoom (wheel), reset (R or double
// click). OpenGL 3.3 core through Qt; one VBO per organ, rebuilt when a snapshot arrives.
#pragma once

#include <QMatrix4x4>
#include <QOpenGLBuffer>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVertexArrayObject>
#include <QOpenGLWidget>
#include <QVector3D>
#include <memory>
#include <optional>
#include <vector>

#include "leafdig/acquisition/session.hpp"

namespace leafdig::station {

class PreviewWidget : public QOpenGLWidget, protected QOpenGLFunctions_3_3_Core {
  Q_OBJECT

 public:
  explicit PreviewWidget(QWidget* parent = nullptr);
  ~PreviewWidget() override;

  // Shows this snapshot (latest wins; called on the UI thread).
  void show(const acquisition::Snapshot& snapshot);
  void resetView();
  // The stylus where it is now (a cross-hair point), or none.
  void setStylusCursor(const std::optional<acquisition::Vec3>& positionMm);
  // A marker to highlight (review selection), or none.
  void setHighlight(const std::optional<acquisition::Item>& item);
  [[nodiscard]] const std::optional<acquisition::Item>& highlight() const { return highlight_; }
  // The stylus item drawn nearest to a widget position (within `radiusPx`), for picking.
  [[nodiscard]] std::optional<acquisition::Item> itemAt(QPointF pos, double radiusPx = 14.0) const;
  // Where an item is drawn (widget coordinates) with the current view.
  [[nodiscard]] QPointF project(const acquisition::Vec3& positionMm) const;
  // Frame time of the last paint, and how many triangles it drew (for tests and benchmarks).
  [[nodiscard]] double lastFrameMs() const { return lastFrameMs_; }
  [[nodiscard]] std::size_t trianglesDrawn() const { return trianglesDrawn_; }

 signals:
  void itemPicked(const leafdig::acquisition::Item& item);

 protected:
  void initializeGL() override;
  void resizeGL(int w, int h) override;
  void paintGL() override;
  void mousePressEvent(QMouseEvent* e) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mouseReleaseEvent(QMouseEvent* e) override;
  void mouseDoubleClickEvent(QMouseEvent* e) override;
  void wheelEvent(QWheelEvent* e) override;
  void keyPressEvent(QKeyEvent* e) override;

 private:
  struct Batch {
    std::unique_ptr<QOpenGLVertexArrayObject> vao;
    QOpenGLBuffer vbo{QOpenGLBuffer::VertexBuffer};
    int count = 0;
    QVector3D colour;
    bool points = false;
  };
  void upload();
  [[nodiscard]] QMatrix4x4 viewProjection() const;
  void addBatch(const std::vector<float>& data, QVector3D colour, bool points);

  QOpenGLShaderProgram program_;
  std::vector<Batch> batches_;
  std::shared_ptr<const acquisition::Preview> preview_;
  std::vector<acquisition::Item> items_;
  bool dirty_ = false, glReady_ = false, userMoved_ = false;
  QVector3D centre_{0, 0, 0};
  float radius_ = 100.0f, yaw_ = -30.0f, pitch_ = 35.0f, distance_ = 3.0f;
  QVector3D pan_{0, 0, 0};
  QPoint lastMouse_, pressedAt_;
  bool dragged_ = false;
  std::optional<acquisition::Vec3> cursor_;
  std::optional<acquisition::Item> highlight_;
  double lastFrameMs_ = 0;
  std::size_t trianglesDrawn_ = 0;
};

}  // namespace leafdig::station
