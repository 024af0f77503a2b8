// The live 3D preview: the snapshot's vein tubes and blade, the markers, the last accepted
// point highlighted; orbit (left drag), pan (right drag), zoom (wheel), reset (R or double
// click). OpenGL 3.3 core through Qt.
//
// The GL drawing lives in its own native window (a QOpenGLWindow in a window container),
// not a QOpenGLWidget: a QOpenGLWidget makes Qt compose the whole top-level window with
// OpenGL at every update of any widget in it, which with software OpenGL (llvmpipe) costs
// more than drawing the leaf. See docs/benchmarks.md ("Station preview").
#pragma once

#include <QElapsedTimer>
#include <QImage>
#include <QMatrix4x4>
#include <QOpenGLBuffer>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVertexArrayObject>
#include <QOpenGLWindow>
#include <QTimer>
#include <QVector3D>
#include <QWidget>
#include <memory>
#include <optional>
#include <vector>

#include "leafdig/acquisition/session/session.hpp"
#include "preview/view_framing.hpp"

namespace leafdig::station {

class PreviewWidget;

// The GL window: draws what its PreviewWidget holds, passes input back to it.
class PreviewSurface : public QOpenGLWindow, protected QOpenGLFunctions_3_3_Core {
 public:
  explicit PreviewSurface(PreviewWidget* owner);
  ~PreviewSurface() override;
  // Renders one frame into an image of the surface's size (screenshots, tests).
  [[nodiscard]] QImage render(QSize size);

 protected:
  void initializeGL() override;
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
    QOpenGLBuffer ibo{QOpenGLBuffer::IndexBuffer};  // meshes: shared vertices, drawn indexed
    int count = 0;                                  // indices (meshes) or points
    QVector3D colour;
    bool points = false, cull = false;
  };
  void upload();
  void draw(QSize size);
  static void release(std::vector<Batch>& batches);
  // `data`: position and normal per vertex; `indices`: triangles (empty for points).
  void addBatch(std::vector<Batch>& into, const std::vector<float>& data, const std::vector<std::uint32_t>& indices,
                QVector3D colour, bool points, bool cull = false);

  PreviewWidget* owner_;
  QOpenGLShaderProgram program_;
  std::vector<Batch> meshes_, points_;         // rebuilt when the leaf changes / when a marker or the cursor does
  const model::LeafMesh* uploaded_ = nullptr;  // the mesh in meshes_ (a level of the preview)
  bool glReady_ = false;
};

class PreviewWidget : public QWidget {
  Q_OBJECT

 public:
  explicit PreviewWidget(QWidget* parent = nullptr);
  ~PreviewWidget() override;

  // Shows this snapshot (latest wins; called on the UI thread). Until the operator moves the
  // view, the leaf is kept framed: the view glides to a new framing only when the leaf
  // grows out of the current one (or shrinks to under half of it), so it does not jump at
  // every point.
  void show(const acquisition::Snapshot& snapshot);
  // Back to the automatic framing (R, double click).
  void resetView();
  // A live capture leaves room for the leaf to grow in each new framing; review does not.
  void setLive(bool live) { live_ = live; }
  [[nodiscard]] const ViewFraming& framing() const { return view_; }
  // How often the automatic framing moved, and whether a move is under way.
  [[nodiscard]] int framingChanges() const { return framingChanges_; }
  [[nodiscard]] bool animating() const { return animation_.isActive(); }
  void finishAnimation();
  // The stylus where it is now (a cross-hair point), or none.
  void setStylusCursor(const std::optional<acquisition::Vec3>& positionMm);
  // A marker to highlight (review selection), or none.
  void setHighlight(const std::optional<acquisition::Item>& item);
  [[nodiscard]] const std::optional<acquisition::Item>& highlight() const { return highlight_; }
  // The stylus item drawn nearest to a widget position (within `radiusPx`), for picking.
  [[nodiscard]] std::optional<acquisition::Item> itemAt(QPointF pos, double radiusPx = 14.0) const;
  // Where an item is drawn (widget coordinates) with the current view.
  [[nodiscard]] QPointF project(const acquisition::Vec3& positionMm) const;
  // Asks for a new frame (the GL window repaints on its own for every change above).
  void redraw();
  // No OpenGL here: a message takes the 3D view's place (the rest of the station works).
  void showUnavailable();
  [[nodiscard]] bool unavailable() const;
  // The preview as drawn now, at the widget's size (rendered off-screen; empty without GL).
  [[nodiscard]] QImage grabFramebuffer();
  // The window as on screen: QWidget::grab() with every visible preview in it drawn in.
  [[nodiscard]] static QImage grabWindow(QWidget* window);
  // Frame time of the last paint, and how many triangles it drew (for tests and benchmarks).
  [[nodiscard]] double lastFrameMs() const { return lastFrameMs_; }
  [[nodiscard]] std::size_t trianglesDrawn() const { return trianglesDrawn_; }
  // Screen pixels per millimetre at the view's centre, and the preview mesh drawn for it: the
  // coarsest level whose error is under half a pixel (else the finest), or the preview's one
  // mesh when it has no levels. drawnErrorMm() is that level's error (0: the one mesh).
  [[nodiscard]] double pixelsPerMm() const;
  [[nodiscard]] const model::LeafMesh* meshForView() const;
  [[nodiscard]] double drawnErrorMm() const;

 signals:
  void itemPicked(const leafdig::acquisition::Item& item);
  void frameSwapped();  // a frame of the preview reached the screen

 protected:
  void keyPressEvent(QKeyEvent* e) override;
  void resizeEvent(QResizeEvent* e) override;

 private:
  friend class PreviewSurface;
  // The points the framing keeps in view (the preview's vertices and the stylus items).
  [[nodiscard]] std::vector<QVector3D> scenePoints() const;
  // Points a new framing also covers while the leaf is still growing.
  [[nodiscard]] std::vector<QVector3D> roomToGrow() const;
  void keepFramed(bool force);
  void glideTo(const ViewFraming& target);
  void stopGliding();
  [[nodiscard]] QMatrix4x4 viewProjection(QSizeF size) const;
  void changed(bool geometry);
  void onPress(QPointF pos);
  void onMove(QPointF pos, Qt::MouseButtons buttons);
  void onRelease(QPointF pos, Qt::MouseButton button);
  void onWheel(int angleDeltaY);

  PreviewSurface* surface_;
  QWidget* container_ = nullptr;
  QWidget* unavailable_ = nullptr;
  std::shared_ptr<const acquisition::Preview> preview_;
  std::vector<acquisition::Item> items_;
  bool meshDirty_ = false, pointsDirty_ = false, userMoved_ = false;
  ViewFraming view_, from_, to_;  // shown now; a glide goes from from_ to to_
  bool framed_ = false, yawFixed_ = false, rowsEnded_ = false, live_ = true;
  int framingChanges_ = 0;
  QTimer animation_;
  QElapsedTimer animationClock_;
  QPointF lastMouse_, pressedAt_;
  bool dragged_ = false;
  std::optional<acquisition::Vec3> cursor_;
  std::optional<acquisition::Item> highlight_;
  double lastFrameMs_ = 0;
  std::size_t trianglesDrawn_ = 0;
};

}  // namespace leafdig::station
