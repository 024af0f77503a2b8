#include "preview/preview_widget.hpp"

#include <QElapsedTimer>
#include <QKeyEvent>
#include <QLabel>
#include <QMouseEvent>
#include <QOpenGLFramebufferObject>
#include <QPainter>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <cmath>
#include <cstring>
#include <numbers>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace leafdig::station {
namespace {

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 mvp;
uniform mat4 model;
uniform float pointSize;
out vec3 vNormal;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  gl_PointSize = pointSize;
  vNormal = mat3(model) * normal;
})";

const char* kFragment = R"(#version 330 core
in vec3 vNormal;
uniform vec3 colour;
uniform bool lit;
out vec4 fragColour;
void main() {
  if (!lit) { fragColour = vec4(colour, 1.0); return; }
  vec3 n = normalize(vNormal);
  vec3 l = normalize(vec3(0.4, 0.5, 0.8));
  float d = abs(dot(n, l));  // the blade is seen from both sides
  fragColour = vec4(colour * (0.3 + 0.7 * d), 1.0);
})";

// Mesa's software rasterisers (llvmpipe) allocate several MB of vertex and bin memory per
// frame and free it again. glibc hands memory above 128 KB back to the kernel at once (munmap,
// heap trim), so every frame page-faulted ~11 MB of fresh zeroed pages: a third of the
// frame time of the 17-row leaf at the export resolution went to the kernel. Keeping up to
// 64 MB of freed heap for reuse removes that (docs/benchmarks.md, "Station preview").
void keepFreedMemoryForSoftwareGl(const char* renderer) {
#ifdef __GLIBC__
  static bool done = false;
  if (done || renderer == nullptr ||
      (std::strstr(renderer, "llvmpipe") == nullptr && std::strstr(renderer, "softpipe") == nullptr))
    return;
  done = true;
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);  // the largest glibc accepts; bigger blocks still map
  mallopt(M_TRIM_THRESHOLD, 64 * 1024 * 1024);
#else
  (void)renderer;
#endif
}

// Digitizer frame (Z up) to the view: X right, Z up → GL Y up.
QVector3D toView(const Eigen::Vector3d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.z()), static_cast<float>(-p.y())};
}
QVector3D toView(const acquisition::Vec3& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[2]), static_cast<float>(-p[1])};
}

// The automatic framing (PreviewWidget::keepFramed).
constexpr float kPitchDeg = 55.0f;  // looking down on the leaf at an angle
constexpr float kFill = 0.8f;       // a new framing fills this much of the view…
constexpr float kInside = 0.94f;    // …and holds while everything stays this far inside
constexpr float kMinFill = 0.45f;   // and fills at least this much in one direction
constexpr int kGlideMs = 250;
constexpr float kMinHalfSizeMm = 40.0f;  // the tip alone: an 80 mm field around it
constexpr float kGrowthRoom = 2.0f;      // while rows are taken: room for twice as much again…
constexpr float kWidthRoom = 1.4f;       // …and for a wider leaf

}  // namespace

// ---- PreviewSurface: the GL window ----

PreviewSurface::PreviewSurface(PreviewWidget* owner) : owner_(owner) {
  // Keys stay with the station window (its shortcuts and the held Accept key).
  setFlag(Qt::WindowDoesNotAcceptFocus);
}

PreviewSurface::~PreviewSurface() {
  if (!glReady_) return;
  makeCurrent();
  release(meshes_);
  release(points_);
  doneCurrent();
}

void PreviewSurface::initializeGL() {
  // Qt calls this even when it could not create a context (no OpenGL on this display): the
  // station goes on without the 3D view and says so.
  // A context without OpenGL 3.3 core functions (an old driver, Qt's offscreen platform) has
  // none to call: the same as no context, not a crash.
  if (!context() || !context()->isValid() || QOpenGLContext::currentContext() != context() ||
      !initializeOpenGLFunctions()) {
    QMetaObject::invokeMethod(
        owner_, [o = owner_] { o->showUnavailable(); }, Qt::QueuedConnection);
    return;
  }
  program_.addShaderFromSourceCode(QOpenGLShader::Vertex, kVertex);
  program_.addShaderFromSourceCode(QOpenGLShader::Fragment, kFragment);
  program_.link();
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_PROGRAM_POINT_SIZE);
  keepFreedMemoryForSoftwareGl(reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  glReady_ = true;
}

void PreviewSurface::release(std::vector<Batch>& batches) {
  for (auto& b : batches) {
    b.vbo.destroy();
    b.ibo.destroy();
  }
  batches.clear();
}

void PreviewSurface::addBatch(std::vector<Batch>& into, const std::vector<float>& data,
                              const std::vector<std::uint32_t>& indices, QVector3D colour, bool points, bool cull) {
  Batch b;
  b.vao = std::make_unique<QOpenGLVertexArrayObject>();
  b.vao->create();
  b.vao->bind();
  b.vbo.create();
  b.vbo.bind();
  b.vbo.allocate(data.data(), static_cast<int>(data.size() * sizeof(float)));
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  if (!indices.empty()) {
    b.ibo.create();
    b.ibo.bind();  // recorded by the VAO
    b.ibo.allocate(indices.data(), static_cast<int>(indices.size() * sizeof(std::uint32_t)));
  }
  b.vao->release();
  b.count = static_cast<int>(indices.empty() ? data.size() / 6 : indices.size());
  b.colour = colour;
  b.points = points;
  b.cull = cull;
  into.push_back(std::move(b));
}

void PreviewSurface::upload() {
  const PreviewWidget& w = *owner_;
  // The level of detail follows the zoom: a new one is uploaded when the view needs another.
  const model::LeafMesh* mesh = w.meshForView();
  if (w.meshDirty_ || mesh != uploaded_) {
    release(meshes_);
    uploaded_ = mesh;
    if (mesh) {
      // One batch for the veins and one for the blade: each vertex once, triangles as
      // indices (a software rasteriser shades a shared vertex once, not six times). The vein
      // tubes are closed and wound outwards (tested in the model), so their back faces are
      // culled; the blade is seen from both sides.
      std::vector<float> data[2];
      std::vector<std::uint32_t> indices[2];
      for (const auto& o : mesh->organs) {
        const int k = o.kind == model::OrganKind::Blade ? 1 : 0;
        const auto base = static_cast<std::uint32_t>(data[k].size() / 6);
        data[k].reserve(data[k].size() + o.mesh.positions.size() * 6);
        for (std::size_t v = 0; v < o.mesh.positions.size(); ++v) {
          const QVector3D p = toView(o.mesh.positions[v]);
          const QVector3D n = toView(o.mesh.normals[v]);
          data[k].insert(data[k].end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
        }
        indices[k].reserve(indices[k].size() + o.mesh.triangles.size() * 3);
        for (const auto& t : o.mesh.triangles)
          for (const auto idx : t) indices[k].push_back(base + idx);
      }
      if (!indices[0].empty()) addBatch(meshes_, data[0], indices[0], QVector3D(0.86f, 0.80f, 0.55f), false, true);
      if (!indices[1].empty()) addBatch(meshes_, data[1], indices[1], QVector3D(0.35f, 0.62f, 0.30f), false);
    }
  }
  if (w.pointsDirty_) {
    release(points_);
    std::vector<float> markers, last;
    const acquisition::Item* lastStylus = nullptr;
    for (const auto& i : w.items_)
      if (acquisition::isStylusItem(i.what)) lastStylus = &i;
    for (const auto& i : w.items_) {
      if (!acquisition::isStylusItem(i.what)) continue;
      const QVector3D p = toView(i.positionMm);
      auto& into = &i == lastStylus ? last : markers;
      into.insert(into.end(), {p.x(), p.y(), p.z(), 0.f, 1.f, 0.f});
    }
    if (!markers.empty()) addBatch(points_, markers, {}, QVector3D(0.15f, 0.35f, 0.85f), true);
    if (!last.empty()) addBatch(points_, last, {}, QVector3D(0.95f, 0.25f, 0.15f), true);
    if (w.highlight_ && acquisition::isStylusItem(w.highlight_->what)) {
      const QVector3D p = toView(w.highlight_->positionMm);
      addBatch(points_, {p.x(), p.y(), p.z(), 0.f, 1.f, 0.f}, {}, QVector3D(1.0f, 0.85f, 0.0f), true);
    }
    if (w.cursor_) {
      const QVector3D p = toView(*w.cursor_);
      addBatch(points_, {p.x(), p.y(), p.z(), 0.f, 1.f, 0.f}, {}, QVector3D(0.8f, 0.1f, 0.8f), true);
    }
  }
  owner_->meshDirty_ = owner_->pointsDirty_ = false;
}

void PreviewSurface::draw(QSize size) {
  QElapsedTimer timer;
  timer.start();
  upload();
  glViewport(0, 0, size.width(), size.height());
  glClearColor(0.96f, 0.96f, 0.94f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  program_.bind();
  program_.setUniformValue("mvp", owner_->viewProjection(QSizeF(size)));
  program_.setUniformValue("model", QMatrix4x4());
  std::size_t triangles = 0;
  for (auto* batches : {&meshes_, &points_})
    for (auto& b : *batches) {
      program_.setUniformValue("colour", b.colour);
      program_.setUniformValue("lit", !b.points);
      program_.setUniformValue("pointSize", b.colour.x() > 0.79f ? 13.0f : 7.0f);
      if (b.cull)
        glEnable(GL_CULL_FACE);
      else
        glDisable(GL_CULL_FACE);
      b.vao->bind();
      if (b.points) {
        glDrawArrays(GL_POINTS, 0, b.count);
      } else {
        glDrawElements(GL_TRIANGLES, b.count, GL_UNSIGNED_INT, nullptr);
        triangles += static_cast<std::size_t>(b.count / 3);
      }
      b.vao->release();
    }
  program_.release();
  glFinish();
  owner_->trianglesDrawn_ = triangles;
  owner_->lastFrameMs_ = static_cast<double>(timer.nsecsElapsed()) / 1e6;
}

void PreviewSurface::paintGL() {
  if (glReady_) draw(size() * devicePixelRatio());
}

QImage PreviewSurface::render(QSize size) {
  if (!glReady_ || !isValid() || size.isEmpty()) return {};
  makeCurrent();
  QOpenGLFramebufferObject fbo(size, QOpenGLFramebufferObject::CombinedDepthStencil);
  fbo.bind();
  draw(size);
  QImage image = fbo.toImage();
  fbo.release();
  doneCurrent();
  return image;
}

void PreviewSurface::mousePressEvent(QMouseEvent* e) {
  if (owner_->focusPolicy() & Qt::ClickFocus) owner_->setFocus(Qt::MouseFocusReason);
  owner_->onPress(e->position());
}
void PreviewSurface::mouseMoveEvent(QMouseEvent* e) {
  owner_->onMove(e->position(), e->buttons());
}
void PreviewSurface::mouseReleaseEvent(QMouseEvent* e) {
  owner_->onRelease(e->position(), e->button());
}
void PreviewSurface::mouseDoubleClickEvent(QMouseEvent*) {
  owner_->resetView();
}
void PreviewSurface::wheelEvent(QWheelEvent* e) {
  owner_->onWheel(e->angleDelta().y());
}
void PreviewSurface::keyPressEvent(QKeyEvent* e) {
  if (e->key() == Qt::Key_R)
    owner_->resetView();
  else
    QOpenGLWindow::keyPressEvent(e);
}

// ---- PreviewWidget: what is shown, and the view ----

namespace {
// Whether this display can give an OpenGL context at all (checked once): a QOpenGLWindow
// without one crashes inside Qt on its first paint.
bool openGlAvailable() {
  static const bool available = [] {
    QOpenGLContext probe;
    return probe.create();
  }();
  return available;
}
}  // namespace

PreviewWidget::PreviewWidget(QWidget* parent)
    : QWidget(parent), surface_(openGlAvailable() ? new PreviewSurface(this) : nullptr) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  // The container owns the surface. Without OpenGL an empty widget holds the place.
  container_ = surface_ ? QWidget::createWindowContainer(surface_, this) : new QWidget(this);
  container_->setFocusPolicy(Qt::NoFocus);
  layout->addWidget(container_);
  setFocusPolicy(Qt::ClickFocus);
  setMinimumSize(320, 240);
  if (surface_) connect(surface_, &QOpenGLWindow::frameSwapped, this, &PreviewWidget::frameSwapped);
  auto* message = new QLabel(tr("3D preview unavailable: this display has no OpenGL.\nCapture, the step list and the "
                                "schematic work as usual."),
                             this);
  message->setAlignment(Qt::AlignCenter);
  message->setWordWrap(true);
  message->hide();
  unavailable_ = message;
  layout->addWidget(unavailable_);
  if (!surface_) showUnavailable();
  animation_.setInterval(16);
  connect(&animation_, &QTimer::timeout, this, [this] {
    const float t = std::min(1.0f, static_cast<float>(animationClock_.elapsed()) / static_cast<float>(kGlideMs));
    view_ = blend(from_, to_, t);
    if (t >= 1.0f) animation_.stop();
    redraw();
  });
}

// The surface reads this widget's state: it goes first, while that state is whole.
PreviewWidget::~PreviewWidget() {
  delete container_;
}

void PreviewWidget::changed(bool geometry) {
  meshDirty_ = meshDirty_ || geometry;
  pointsDirty_ = true;
  redraw();
}

void PreviewWidget::redraw() {
  if (surface_) surface_->update();
}

bool PreviewWidget::unavailable() const {
  return !unavailable_->isHidden();
}

void PreviewWidget::showUnavailable() {
  if (!unavailable_->isHidden()) return;
  container_->hide();
  unavailable_->show();
}

QImage PreviewWidget::grabFramebuffer() {
  return surface_ ? surface_->render(size() * devicePixelRatio()) : QImage();
}

QImage PreviewWidget::grabWindow(QWidget* window) {
  QImage image = window->grab().toImage();
  QPainter painter(&image);
  for (PreviewWidget* p : window->findChildren<PreviewWidget*>()) {
    if (!p->isVisible()) continue;
    const QImage frame = p->grabFramebuffer();
    if (!frame.isNull()) painter.drawImage(QRect(p->mapTo(window, QPoint(0, 0)), p->size()), frame);
  }
  return image;
}

void PreviewWidget::show(const acquisition::Snapshot& s) {
  preview_ = s.preview;
  items_ = s.items;
  // The rows just ended: the room left for growth is not needed any more.
  const bool rowsJustEnded = s.rowsEnded && !rowsEnded_;
  rowsEnded_ = s.rowsEnded;
  if (!userMoved_) keepFramed(rowsJustEnded);
  changed(true);
}

std::vector<QVector3D> PreviewWidget::scenePoints() const {
  // The markers: the blade and veins pass through them (a tube is a millimetre or two
  // wider), and there are a hundred of them instead of the mesh's 85 000 vertices, so
  // framing costs nothing on the way from snapshot to screen.
  std::vector<QVector3D> points;
  for (const auto& i : items_)
    if (acquisition::isStylusItem(i.what) && i.what != acquisition::What::Board) points.push_back(toView(i.positionMm));
  if (points.empty() && preview_)
    for (const auto& o : preview_->mesh.organs)
      for (const auto& p : o.mesh.positions) points.push_back(toView(p));
  return points;
}

std::vector<QVector3D> PreviewWidget::roomToGrow() const {
  // While rows are still being taken the leaf grows towards its base and widens: a new
  // framing leaves room for twice the midrib so far and a wider newest row, so the view
  // moves a few times during a leaf, not at every row.
  std::vector<QVector3D> room;
  if (rowsEnded_ || !live_) return room;
  const auto* tip = acquisition::findItem(items_, acquisition::What::Tip, 0, 0);
  const acquisition::Item* last = nullptr;
  for (const auto& i : items_)
    if (i.what == acquisition::What::Marker && i.col == 4 && (!last || i.row > last->row)) last = &i;
  if (!tip || !last) return room;
  const QVector3D a = toView(tip->positionMm), b = toView(last->positionMm);
  const QVector3D ahead = b + (b - a) * kGrowthRoom;
  room.push_back(ahead);
  for (const int col : {1, acquisition::kMarkersPerRow})
    if (const auto* margin = acquisition::findItem(items_, acquisition::What::Marker, last->row, col))
      room.push_back(ahead + (toView(margin->positionMm) - b) * kWidthRoom);
  return room;
}

void PreviewWidget::keepFramed(bool force) {
  const std::vector<QVector3D> points = scenePoints();
  if (points.empty()) return;
  const float aspect = static_cast<float>(width()) / static_cast<float>(std::max(1, height()));
  // The leaf's direction is known once a row is taken: tip on the left, the rows going right.
  if (!yawFixed_) {
    const auto* tip = acquisition::findItem(items_, acquisition::What::Tip, 0, 0);
    const auto* midrib = acquisition::findItem(items_, acquisition::What::Marker, 1, 4);
    if (tip && midrib) {
      to_.yawDeg = yawAcross(toView(midrib->positionMm) - toView(tip->positionMm));
      yawFixed_ = true;
      force = true;
    }
  }
  // The framing holds while what is there stays inside, and what is there plus the room
  // left for growth fills enough of the view.
  const std::vector<QVector3D> room = roomToGrow();
  std::vector<QVector3D> withRoom = points;
  withRoom.insert(withRoom.end(), room.begin(), room.end());
  const bool inside = framed_ && framingHolds(to_, points, aspect, kInside, 0.0f);
  if (!force && inside && framingHolds(to_, withRoom, aspect, 1e9f, kMinFill)) return;
  const ViewFraming target = fitView(withRoom, aspect, to_.yawDeg, kPitchDeg, kFill, kMinHalfSizeMm);
  // Small in the view but already shown as large as allowed (the first points): stay.
  const float scale = target.distance * target.radius, current = to_.distance * to_.radius;
  if (!force && inside && std::abs(scale - current) < 0.15f * current &&
      (target.centre - to_.centre).length() < 0.1f * current)
    return;
  if (!framed_) {
    view_ = from_ = to_ = target;  // the first framing: no glide from nowhere
    framed_ = true;
    redraw();
  } else {
    glideTo(target);
  }
  ++framingChanges_;
}

void PreviewWidget::glideTo(const ViewFraming& target) {
  from_ = view_;
  to_ = target;
  animationClock_.start();
  if (!animation_.isActive()) animation_.start();
}

void PreviewWidget::stopGliding() {
  animation_.stop();
  to_ = view_;
}

void PreviewWidget::finishAnimation() {
  animation_.stop();
  view_ = to_;
  redraw();
}

void PreviewWidget::resetView() {
  stopGliding();
  userMoved_ = false;
  framed_ = framed_ && yawFixed_;
  yawFixed_ = false;
  keepFramed(true);
  redraw();
}

void PreviewWidget::resizeEvent(QResizeEvent* e) {
  QWidget::resizeEvent(e);
  if (!userMoved_ && framed_) keepFramed(false);
}

void PreviewWidget::setStylusCursor(const std::optional<acquisition::Vec3>& positionMm) {
  if (positionMm == cursor_) return;
  cursor_ = positionMm;
  changed(false);
}

void PreviewWidget::setHighlight(const std::optional<acquisition::Item>& item) {
  highlight_ = item;
  changed(false);
}

double PreviewWidget::pixelsPerMm() const {
  // A millimetre at the centre of the view, distance × radius away, through the vertical
  // field of view onto the widget's height in device pixels.
  const double depth = static_cast<double>(view_.distance) * static_cast<double>(view_.radius);
  const double halfHeight = depth * std::tan(static_cast<double>(kFovYDeg) * std::numbers::pi / 360.0);
  return halfHeight > 0 ? 0.5 * static_cast<double>(height()) * devicePixelRatioF() / halfHeight : 0.0;
}

const model::LeafMesh* PreviewWidget::meshForView() const {
  if (!preview_) return nullptr;
  if (preview_->levels.empty()) return &preview_->mesh;
  const double halfPixelMm = pixelsPerMm() > 0 ? 0.5 / pixelsPerMm() : 0.0;
  for (const auto& level : preview_->levels)  // coarse to fine
    if (level.maxErrorMm <= halfPixelMm) return &level.mesh;
  return &preview_->levels.back().mesh;
}

double PreviewWidget::drawnErrorMm() const {
  if (!preview_) return 0.0;
  const model::LeafMesh* mesh = meshForView();
  for (const auto& level : preview_->levels)
    if (&level.mesh == mesh) return level.maxErrorMm;
  return 0.0;
}

QMatrix4x4 PreviewWidget::viewProjection(QSizeF size) const {
  return view_.matrix(static_cast<float>(size.width() / std::max(1.0, size.height())));
}

QPointF PreviewWidget::project(const acquisition::Vec3& positionMm) const {
  const QVector3D ndc = viewProjection(QSizeF(size())).map(toView(positionMm));
  return {(ndc.x() + 1.0) * 0.5 * width(), (1.0 - ndc.y()) * 0.5 * height()};
}

std::optional<acquisition::Item> PreviewWidget::itemAt(QPointF pos, double radiusPx) const {
  std::optional<acquisition::Item> best;
  double bestD = radiusPx;
  for (const auto& i : items_) {
    if (!acquisition::isStylusItem(i.what)) continue;
    const double d = QLineF(project(i.positionMm), pos).length();
    if (d <= bestD) {
      bestD = d;
      best = i;
    }
  }
  return best;
}

void PreviewWidget::onPress(QPointF pos) {
  lastMouse_ = pressedAt_ = pos;
  dragged_ = false;
}

void PreviewWidget::onRelease(QPointF pos, Qt::MouseButton button) {
  // A click (not a drag) picks the marker under the pointer.
  if (!dragged_ && button == Qt::LeftButton)
    if (const auto item = itemAt(pos)) emit itemPicked(*item);
}

void PreviewWidget::onMove(QPointF pos, Qt::MouseButtons buttons) {
  const QPointF d = pos - lastMouse_;
  lastMouse_ = pos;
  if ((lastMouse_ - pressedAt_).manhattanLength() > 3) {
    dragged_ = true;
    userMoved_ = true;
    stopGliding();
  }
  if (buttons & Qt::LeftButton) {
    view_.yawDeg += 0.4f * static_cast<float>(d.x());
    view_.pitchDeg = std::clamp(view_.pitchDeg + 0.4f * static_cast<float>(d.y()), -89.0f, 89.0f);
  } else if (buttons & Qt::RightButton) {
    view_.pan += QVector3D(0.003f * static_cast<float>(d.x()), -0.003f * static_cast<float>(d.y()), 0) * view_.distance;
  }
  redraw();
}

void PreviewWidget::onWheel(int angleDeltaY) {
  stopGliding();
  view_.distance = std::clamp(view_.distance * std::pow(0.999f, static_cast<float>(angleDeltaY)), 0.3f, 30.0f);
  userMoved_ = true;
  redraw();
}

void PreviewWidget::keyPressEvent(QKeyEvent* e) {
  if (e->key() == Qt::Key_R)
    resetView();
  else
    QWidget::keyPressEvent(e);
}

}  // namespace leafdig::station
