// The links for every device leafdig speaks: configuration and factories.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "leafdig/devices/codecs/line_digitizer.hpp"
#include "leafdig/devices/links/driver.hpp"
#include "leafdig/devices/transports/hid.hpp"
#include "leafdig/devices/transports/serial_port.hpp"
#include "leafdig/devices/transports/usb.hpp"

namespace leafdig::devices {

enum class DigitizerKind { Fastrak, Patriot, Liberty, MicroScribe, Line };
enum class CaliperKind { Hid, UsbItn, Mitutoyo, UWave, Sylvac };
[[nodiscard]] const char* toString(DigitizerKind k);
[[nodiscard]] const char* toString(CaliperKind k);
[[nodiscard]] DigitizerKind digitizerKindFromString(const std::string& s);  // throws UnknownName
[[nodiscard]] CaliperKind caliperKindFromString(const std::string& s);

struct DigitizerConfig {
  DigitizerKind kind = DigitizerKind::Fastrak;
  std::string port;
  int baud = 0;            // 0: the device's usual rate
  bool autobaud = true;    // try the other usual rates when the device does not answer
  bool binary = false;     // FASTRAK / Patriot / Liberty binary records
  std::string hemisphere;  // FASTRAK "0,0,1" → "H1,0,0,1"; empty: leave as is
  // The stream's record rate, for timing records by the device's clock (RecordClock); 0: the
  // device's own (FASTRAK 120 Hz, Patriot 60 Hz, Liberty 240 Hz). A simulator says its own.
  double recordRateHz = 0;
  // A reference receiver (FASTRAK 2-4, Patriot 2, Liberty 2-16; 0: none): the stylus is
  // receiver 1 and every stylus sample is delivered in this receiver's frame (reference.hpp).
  int referenceStation = 0;
  double referenceJumpMm = 10.0, referenceJumpDeg = 5.0;  // a jump between two of its records
  // The stylus' tip in its sensor's frame (a tip calibration, docs/devices.md, "The stylus tip"):
  // every stylus sample is delivered at p + R·tip, its tip, before a reference receiver's frame
  // is applied; a sample without an orientation is withheld (the link asks for one). FASTRAK,
  // Patriot and Liberty; none: the digitizer reports the tip itself.
  std::optional<Vec3> tipOffsetMm;
  line::Config line;  // for DigitizerKind::Line
  // Opens the port; defaults to openSerialPort. Tests substitute their own.
  std::function<std::unique_ptr<SerialPort>(const std::string&, const SerialSettings&)> openPort;
};

struct CaliperConfig {
  CaliperKind kind = CaliperKind::Sylvac;
  std::string port;                // serial kinds
  std::uint16_t vid = 0, pid = 0;  // HID / USB-ITN (defaults: Mitutoyo USB-ITN 0fe7:4001)
  std::string hidPath;             // HID by path instead of id
  int baud = 0;                    // 0: the gauge's usual rate
  std::string unit = "mm";         // Mitutoyo ASCII: "mm", "in" or "auto"
  bool grabKeyboard = true;        // HID: EVIOCGRAB the gauge's evdev nodes
  bool dtrTrigger = false;         // Sylvac simplex cable: request by dropping DTR
  std::function<std::unique_ptr<SerialPort>(const std::string&, const SerialSettings&)> openPort;
  std::function<std::unique_ptr<HidDevice>()> openHid;        // default: hidapi
  std::function<std::unique_ptr<UsbVendorDevice>()> openUsb;  // default: libusb
};

[[nodiscard]] SerialSettings defaultSettings(DigitizerKind k);
[[nodiscard]] SerialSettings defaultSettings(CaliperKind k);

[[nodiscard]] std::unique_ptr<DeviceLink> makeDigitizerLink(DigitizerConfig config);
[[nodiscard]] std::unique_ptr<DeviceLink> makeCaliperLink(CaliperConfig config);

// "0fe7:4001" (hex, as lsusb prints it) into vid and pid; false when it is not exactly that.
[[nodiscard]] bool parseVidPid(const std::string& text, std::uint16_t& vid, std::uint16_t& pid);

}  // namespace leafdig::devices
