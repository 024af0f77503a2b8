#include "dialogs/device_fields.hpp"

#include <QHBoxLayout>
#include <QObject>
#include <QPushButton>

#include "leafdig/acquisition/live/device_set.hpp"

namespace leafdig::station {

namespace {

QString hex4(std::uint16_t v) {
  return QString("%1").arg(v, 4, 16, QChar('0'));
}

void fill(QComboBox* box, const std::vector<std::pair<QString, QString>>& choices, const QString& keep) {
  box->clear();
  for (const auto& [label, spec] : choices) box->addItem(label, spec);
  const int at = box->findData(keep);
  if (at >= 0)
    box->setCurrentIndex(at);
  else if (!keep.isEmpty())
    box->setEditText(keep);
}

}  // namespace

QString specOf(const QComboBox* box) {
  const int at = box->findText(box->currentText());
  return at >= 0 ? box->itemData(at).toString() : box->currentText().trimmed();
}

std::vector<std::pair<QString, QString>> digitizerChoices(const devices::Inventory& inv) {
  std::vector<std::pair<QString, QString>> out{
      {QObject::tr("Simulated FASTRAK (virtual technician)"), kSimulatedDigitizer}};
  for (const auto& port : inv.serial) {
    const QString path = QString::fromStdString(port.path);
    const devices::Profile* profile = port.vid && port.pid ? devices::matchProfile(*port.vid, *port.pid) : nullptr;
    const QString what = profile ? QString::fromLatin1(profile->name) : QString::fromStdString(port.description);
    for (const char* kind : {"fastrak", "patriot", "liberty", "microscribe"})
      out.emplace_back(QString("%1 on %2 (%3)").arg(QString::fromLatin1(kind), path, what),
                       QString("%1:%2").arg(kind, path));
  }
  return out;
}

std::vector<std::pair<QString, QString>> caliperChoices(const devices::Inventory& inv) {
  std::vector<std::pair<QString, QString>> out{
      {QObject::tr("Simulated Sylvac (virtual technician)"), kSimulatedCaliper}};
  for (const auto& h : inv.hid) {
    const devices::Profile* profile = devices::matchProfile(h.vid, h.pid);
    const QString what =
        profile ? QString::fromLatin1(profile->name) : QString::fromStdString(h.manufacturer + " " + h.product);
    out.emplace_back(QString("HID %1:%2 (%3)").arg(hex4(h.vid), hex4(h.pid), what.trimmed()),
                     QString("hid:%1:%2").arg(hex4(h.vid), hex4(h.pid)));
  }
  for (const auto& port : inv.serial) {
    const QString path = QString::fromStdString(port.path);
    for (const char* kind : {"sylvac", "mitutoyo", "uwave"})
      out.emplace_back(QString("%1 on %2").arg(QString::fromLatin1(kind), path), QString("%1:%2").arg(kind, path));
  }
  return out;
}

QComboBox* knownNamesBox(const std::set<QString>& names, const std::string& current) {
  auto* box = new QComboBox;
  box->setEditable(true);
  for (const QString& n : names) box->addItem(n);
  box->setEditText(QString::fromStdString(current));
  return box;
}

QLabel* problemLine() {
  auto* line = new QLabel;
  line->setStyleSheet("color:#b71c1c");
  line->setWordWrap(true);
  return line;
}

DeviceFields::DeviceFields(const devices::Inventory& inventory, const QString& digitizer, const QString& caliper)
    : digitizer_(new QComboBox), caliper_(new QComboBox) {
  for (QComboBox* c : {digitizer_, caliper_}) {
    c->setEditable(true);  // a spec can be typed: fastrak:/dev/ttyS0, hid:0fe7:4001
    c->setMinimumContentsLength(34);
  }
  fill(digitizer_, digitizerChoices(inventory), digitizer);
  fill(caliper_, caliperChoices(inventory), caliper);
}

void DeviceFields::addRows(QFormLayout* form) {
  form->addRow(QObject::tr("Digitizer"), digitizer_);
  form->addRow(QObject::tr("Caliper"), caliper_);
  auto* rescanButton = new QPushButton(QObject::tr("Rescan devices"));
  QObject::connect(rescanButton, &QPushButton::clicked, digitizer_, [this] { rescan(devices::takeInventory()); });
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel(QObject::tr("Ports come from the device registry; simulated devices need no hardware.")),
                 1);
  row->addWidget(rescanButton);
  form->addRow(row);
}

void DeviceFields::rescan(const devices::Inventory& inventory) {
  const QString d = specOf(digitizer_), c = specOf(caliper_);
  fill(digitizer_, digitizerChoices(inventory), d);
  fill(caliper_, caliperChoices(inventory), c);
}

std::optional<ChosenDevices> DeviceFields::chosen(QString* problem, const std::string& digitizerOptions) const {
  const auto fail = [problem](const QString& why) -> std::optional<ChosenDevices> {
    if (problem) *problem = why;
    return std::nullopt;
  };
  const QString d = specOf(digitizer_), k = specOf(caliper_);
  const bool simDigitizer = d == kSimulatedDigitizer, simCaliper = k == kSimulatedCaliper;
  if (simDigitizer != simCaliper)
    return fail(
        QObject::tr("The simulated digitizer and caliper work together (a virtual technician uses both): choose "
                    "both or neither."));
  ChosenDevices out;
  out.simulated = simDigitizer;
  if (out.simulated) return out;
  out.digitizer = d.toStdString();
  out.caliper = k.toStdString();
  if (!digitizerOptions.empty() && out.digitizer.find(digitizerOptions) == std::string::npos)
    out.digitizer += digitizerOptions;
  try {
    (void)acquisition::parseDigitizerSpec(out.digitizer);
  } catch (const std::exception& e) {
    return fail(QObject::tr("Digitizer: %1").arg(QString::fromStdString(e.what())));
  }
  try {
    (void)acquisition::parseCaliperSpec(out.caliper);
  } catch (const std::exception& e) {
    return fail(QObject::tr("Caliper: %1").arg(QString::fromStdString(e.what())));
  }
  return out;
}

}  // namespace leafdig::station
