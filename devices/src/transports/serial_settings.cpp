// A serial line's settings in words ("115200 8N1"; serial_port.hpp).
#include <string>

#include "leafdig/devices/transports/serial_port.hpp"

namespace leafdig::devices {

std::string describe(const SerialSettings& s) {
  const char parity = s.parity == Parity::None ? 'N' : s.parity == Parity::Even ? 'E' : 'O';
  return std::to_string(s.baud) + " " + std::to_string(s.dataBits) + parity + std::to_string(s.stopBits) +
         (s.rtsCts ? " RTS/CTS" : "");
}

}  // namespace leafdig::devices
