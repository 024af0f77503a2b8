#include "preview_widget.hpp"

#include <QElapsedTimer>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QWheelEvent>
#include <cmath>

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

// Digitizer frame (Z up) to the view: X right, Z up → GL Y up.
QVector3D toView(const Eigen::Vector3d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.z()), static_cast<float>(-p.y())};
}
QVector3D toView(const acquisition::Vec3& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[2]), static_cast<float>(-p[1])};
}

}  // namespace

PreviewWidget::PreviewWidget(QWidget* parent) : QOpenGLWidget(parent) {
  setFocusPolicy(Qt::ClickFocus);
  setMinimumSize(320, 240);
}

PreviewWidget::~PreviewWidget() {
  makeCurrent();
  for (auto& b : batches_) b.vbo.destroy();
  batches_.clear();
  doneCurrent();
}

void PreviewWidget::show(const acquisition::Snapshot& s) {
  preview_ = s.preview;
  items_ = s.items;
  dirty_ = true;
  // Keep the whole leaf in view as it grows, until the operator moves the view.
  if (!userMoved_) resetView();
  update();
}

void PreviewWidget::resetView() {
  QVector3D lo(1e9f, 1e9f, 1e9f), hi(-1e9f, -1e9f, -1e9f);
  bool any = false;
  const auto grow = [&](const QVector3D& p) {
    any = true;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  };
  if (preview_)
    for (const auto& o : preview_->mesh.organs)
      for (const auto& p : o.mesh.positions) grow(toView(p));
  for (const auto& i : items_)
    if (acquisition::isStylusItem(i.what)) grow(toView(i.positionMm));
  centre_ = any ? (lo + hi) * 0.5f : QVector3D();
  radius_ = any ? std::max(10.0f, (hi - lo).length() * 0.5f) : 100.0f;
  yaw_ = -30.0f;
  pitch_ = 35.0f;
  distance_ = 3.0f;
  pan_ = {};
  userMoved_ = false;
  update();
}

void PreviewWidget::initializeGL() {
  initializeOpenGLFunctions();
  program_.addShaderFromSourceCode(QOpenGLShader::Vertex, kVertex);
  program_.addShaderFromSourceCode(QOpenGLShader::Fragment, kFragment);
  program_.link();
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glReady_ = true;
}

void PreviewWidget::resizeGL(int, int) {}

void PreviewWidget::addBatch(const std::vector<float>& data, QVector3D colour, bool points) {
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
  b.vao->release();
  b.count = static_cast<int>(data.size() / 6);
  b.colour = colour;
  b.points = points;
  batches_.push_back(std::move(b));
}

void PreviewWidget::upload() {
  for (auto& b : batches_) b.vbo.destroy();
  batches_.clear();
  if (preview_) {
    for (const auto& o : preview_->mesh.organs) {
      std::vector<float> data;
      data.reserve(o.mesh.triangles.size() * 18);
      for (const auto& t : o.mesh.triangles)
        for (const auto idx : t) {
          const QVector3D p = toView(o.mesh.positions[idx]);
          const QVector3D n = toView(o.mesh.normals[idx]);
          data.insert(data.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
        }
      const bool blade = o.kind == model::OrganKind::Blade;
      if (!data.empty())
        addBatch(data, blade ? QVector3D(0.35f, 0.62f, 0.30f) : QVector3D(0.86f, 0.80f, 0.55f), false);
    }
  }
  std::vector<float> markers, last;
  const acquisition::Item* lastStylus = nullptr;
  for (const auto& i : items_)
    if (acquisition::isStylusItem(i.what)) lastStylus = &i;
  for (const auto& i : items_) {
    if (!acquisition::isStylusItem(i.what)) continue;
    const QVector3D p = toView(i.positionMm);
    auto& into = &i == lastStylus ? last : markers;
    into.insert(into.end(), {p.x(), p.y(), p.z(), 0.f, 1.f, 0.f});
  }
  if (!markers.empty()) addBatch(markers, QVector3D(0.15f, 0.35f, 0.85f), true);
  if (!last.empty()) addBatch(last, QVector3D(0.95f, 0.25f, 0.15f), true);
  if (highlight_ && acquisition::isStylusItem(highlight_->what)) {
    const QVector3D p = toView(highlight_->positionMm);
    addBatch({p.x(), p.y(), p.z(), 0.f, 1.f, 0.f}, QVector3D(1.0f, 0.85f, 0.0f), true);
  }
  if (cursor_) {
    const QVector3D p = toView(*cursor_);
    addBatch({p.x(), p.y(), p.z(), 0.f, 1.f, 0.f}, QVector3D(0.8f, 0.1f, 0.8f), true);
  }
}

void PreviewWidget::setStylusCursor(const std::optional<acquisition::Vec3>& positionMm) {
  if (positionMm == cursor_) return;
  cursor_ = positionMm;
  dirty_ = true;
  update();
}

void PreviewWidget::setHighlight(const std::optional<acquisition::Item>& item) {
  highlight_ = item;
  dirty_ = true;
  update();
}

QMatrix4x4 PreviewWidget::viewProjection() const {
  QMatrix4x4 projection, view;
  const float aspect = static_cast<float>(width()) / static_cast<float>(std::max(1, height()));
  projection.perspective(35.0f, aspect, radius_ * 0.05f, radius_ * 20.0f);
  view.translate(pan_.x() * radius_, pan_.y() * radius_, -distance_ * radius_);
  view.rotate(pitch_, 1, 0, 0);
  view.rotate(yaw_, 0, 1, 0);
  view.translate(-centre_);
  return projection * view;
}

QPointF PreviewWidget::project(const acquisition::Vec3& positionMm) const {
  const QVector3D ndc = viewProjection().map(toView(positionMm));
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

void PreviewWidget::paintGL() {
  QElapsedTimer timer;
  timer.start();
  if (dirty_) {
    upload();
    dirty_ = false;
  }
  glClearColor(0.96f, 0.96f, 0.94f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  program_.bind();
  program_.setUniformValue("mvp", viewProjection());
  program_.setUniformValue("model", QMatrix4x4());
  trianglesDrawn_ = 0;
  for (auto& b : batches_) {
    program_.setUniformValue("colour", b.colour);
    program_.setUniformValue("lit", !b.points);
    program_.setUniformValue("pointSize", b.colour.x() > 0.79f ? 13.0f : 7.0f);
    b.vao->bind();
    glDrawArrays(b.points ? GL_POINTS : GL_TRIANGLES, 0, b.count);
    if (!b.points) trianglesDrawn_ += static_cast<std::size_t>(b.count / 3);
    b.vao->release();
  }
  program_.release();
  glFinish();
  lastFrameMs_ = static_cast<double>(timer.nsecsElapsed()) / 1e6;
}

void PreviewWidget::mousePressEvent(QMouseEvent* e) {
  lastMouse_ = pressedAt_ = e->position().toPoint();
  dragged_ = false;
}

void PreviewWidget::mouseReleaseEvent(QMouseEvent* e) {
  // A click (not a drag) picks the marker under the pointer.
  if (!dragged_ && e->button() == Qt::LeftButton)
    if (const auto item = itemAt(e->position())) emit itemPicked(*item);
}

void PreviewWidget::mouseMoveEvent(QMouseEvent* e) {
  const QPoint d = e->position().toPoint() - lastMouse_;
  lastMouse_ = e->position().toPoint();
  if ((lastMouse_ - pressedAt_).manhattanLength() > 3) {
    dragged_ = true;
    userMoved_ = true;
  }
  if (e->buttons() & Qt::LeftButton) {
    yaw_ += 0.4f * static_cast<float>(d.x());
    pitch_ = std::clamp(pitch_ + 0.4f * static_cast<float>(d.y()), -89.0f, 89.0f);
  } else if (e->buttons() & Qt::RightButton) {
    pan_ += QVector3D(0.003f * static_cast<float>(d.x()), -0.003f * static_cast<float>(d.y()), 0) * distance_;
  }
  update();
}

void PreviewWidget::mouseDoubleClickEvent(QMouseEvent*) { resetView(); }

void PreviewWidget::wheelEvent(QWheelEvent* e) {
  distance_ = std::clamp(distance_ * std::pow(0.999f, static_cast<float>(e->angleDelta().y())), 0.3f, 20.0f);
  userMoved_ = true;
  update();
}

void PreviewWidget::keyPressEvent(QKeyEvent* e) {
  if (e->key() == Qt::Key_R) resetView();
  else QOpenGLWidget::keyPressEvent(e);
}

}  // namespace leafdig::station
