// libFuzzer target for the field-distortion reader (issue 50): any bytes give a field or a
// FieldDistortionError naming the problem; a crash, another exception or a hang is a finding. A
// field it takes answers everywhere — inside, on and outside its grid — with finite numbers
// within its limits, and writes back to text it reads again.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "leafdig/devices/sim/field_distortion.hpp"

namespace sim = leafdig::devices::sim;

namespace {

void require(bool ok) {
  if (!ok) std::abort();
}

void within(const leafdig::devices::Vec3& v, double limit) {
  for (double x : v) require(std::isfinite(x) && std::abs(x) <= limit);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  sim::FieldDistortion f;
  try {
    f = sim::parseFieldDistortion(text, "fuzz");
  } catch (const sim::FieldDistortionError&) {
    return 0;
  }
  const double far = 1e6;
  for (const leafdig::devices::Vec3 p :
       {f.originMm, leafdig::devices::Vec3{0, 0, 0}, leafdig::devices::Vec3{far, -far, far},
        leafdig::devices::Vec3{f.originMm[0] + 0.37 * f.spacingMm, f.originMm[1] + 1.5 * f.spacingMm,
                               f.originMm[2] + 0.5 * f.spacingMm}}) {
    within(f.displacementAt(p), 1000.0);
    within(f.rotationAt(p), 45.0);
    within(f.reportedOrientation(p, {10, -20, 30}), 360.0);
  }
  const sim::FieldDistortion back = sim::parseFieldDistortion(sim::encodeFieldDistortion(f), "again");
  require(back.displacementMm.size() == f.displacementMm.size() && back.rotationDeg.size() == f.rotationDeg.size());
  return 0;
}
