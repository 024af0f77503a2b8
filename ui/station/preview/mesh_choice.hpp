// How exported meshes are made, as the station offers it (docs/meshing.md): the uniform
// grid of a resolution preset, adaptive meshing within a maximum error, or the seed's rule.
// Shared by the export dialog and the Plant view.
#pragma once

#include <QWidget>

#include "leafdig/model/mesh/mesh_method.hpp"

class QComboBox;
class QDoubleSpinBox;
class QSpinBox;

namespace leafdig::station {

class MeshChoice : public QWidget {
  Q_OBJECT

 public:
  explicit MeshChoice(QWidget* parent = nullptr);
  // The method with its parameters; `resolution` is used for the uniform grid.
  [[nodiscard]] model::MeshOptions options(const std::string& resolution = "export") const;

  [[nodiscard]] QComboBox* method() const { return method_; }
  [[nodiscard]] QDoubleSpinBox* maxError() const { return maxError_; }
  [[nodiscard]] QDoubleSpinBox* minLength() const { return minLength_; }
  [[nodiscard]] QDoubleSpinBox* maxAngle() const { return maxAngle_; }

 private:
  void updateEnabled();
  QComboBox* method_;
  QDoubleSpinBox *maxError_, *minLength_, *maxAngle_;
};

}  // namespace leafdig::station
