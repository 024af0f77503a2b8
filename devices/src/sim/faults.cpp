#include <stdexcept>

#include "leafdig/devices/sim/sim.hpp"

namespace leafdig::devices::sim {

namespace {
double probability(const std::string& key, const std::string& v) {
  std::size_t used = 0;
  double p = -1;
  try {
    p = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || p < 0 || p > 1)
    throw std::invalid_argument("fault '" + key + "': '" + v + "' is not a probability between 0 and 1");
  return p;
}
double seconds(const std::string& key, const std::string& v) {
  std::size_t used = 0;
  double s = -1;
  try {
    s = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || s < 0 || s > 3600)
    throw std::invalid_argument("fault '" + key + "': '" + v + "' is not a duration in seconds");
  return s;
}
}  // namespace

FaultPlan FaultPlan::parse(const std::string& spec) {
  FaultPlan f;
  std::size_t i = 0;
  while (i < spec.size()) {
    std::size_t j = spec.find(',', i);
    if (j == std::string::npos) j = spec.size();
    const std::string item = spec.substr(i, j - i);
    i = j + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument("fault '" + item + "' needs a value, e.g. garbage=0.01 (see 'leafdig sim --help')");
    const std::string key = item.substr(0, eq);
    std::string value = item.substr(eq + 1), extra;
    if (const std::size_t colon = value.find(':'); colon != std::string::npos) {
      extra = value.substr(colon + 1);
      value = value.substr(0, colon);
    }
    if (key == "garbage")
      f.garbage = probability(key, value);
    else if (key == "bitflip")
      f.bitflip = probability(key, value);
    else if (key == "truncate")
      f.truncate = probability(key, value);
    else if (key == "reset")
      f.reset = probability(key, value);
    else if (key == "stall") {
      f.stall = probability(key, value);
      if (!extra.empty()) f.stallSeconds = seconds(key, extra);
    } else if (key == "delay") {
      f.delay = probability(key, value);
      if (!extra.empty()) f.delaySeconds = seconds(key, extra);
    } else if (key == "unplug") {
      f.unplug = probability(key, value);
      if (!extra.empty()) f.unplugSeconds = seconds(key, extra);
    } else if (key == "status") {
      f.status = probability(key, value);
      if (!extra.empty()) {
        if (extra.size() != 1 || !((extra[0] >= 'a' && extra[0] <= 'z') || (extra[0] >= 'A' && extra[0] <= 'Z')))
          throw std::invalid_argument("fault 'status': the code must be one letter, e.g. status=0.01:x");
        f.statusLetter = extra[0];
      }
    } else if (key == "baud") {
      try {
        f.deviceBaud = std::stoi(value);
      } catch (const std::exception&) {
        f.deviceBaud = 0;
      }
      if (f.deviceBaud <= 0) throw std::invalid_argument("fault 'baud': give the device's rate, e.g. baud=9600");
    } else if (key == "seed") {
      try {
        f.seed = std::stoull(value);
      } catch (const std::exception&) {
        throw std::invalid_argument("fault 'seed': '" + value + "' is not a whole number");
      }
    } else {
      throw std::invalid_argument("unknown fault '" + key +
                                  "': use garbage, bitflip, truncate, stall, delay, reset, unplug, status, baud, seed");
    }
  }
  return f;
}

bool FaultPlan::any() const {
  return garbage > 0 || bitflip > 0 || truncate > 0 || stall > 0 || delay > 0 || reset > 0 || unplug > 0 ||
         status > 0 || deviceBaud > 0;
}

}  // namespace leafdig::devices::sim
