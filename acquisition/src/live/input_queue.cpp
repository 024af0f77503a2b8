#include "leafdig/acquisition/live/input_queue.hpp"

namespace leafdig::acquisition::detail {

StylusInput stylusInput(const devices::StylusSample& s, std::int64_t monoNs) {
  return {monoNs, s.positionMm, s.button, s.status, devices::printableRaw(s.raw, true), s.streamBegins};
}

CaliperInput caliperInput(const devices::CaliperReading& r, std::int64_t monoNs) {
  return {monoNs, r.valueMm, devices::printableRaw(r.raw, true)};
}

std::string statusMessage(const devices::DeviceStatus& s) {
  return s.message + (s.remedy.empty() ? "" : " — " + s.remedy);
}

}  // namespace leafdig::acquisition::detail
