// libFuzzer target for one codec, chosen at compile time (LEAFDIG_FUZZ_CODEC). The input is
// fed in chunks whose sizes come from the input itself, so record boundaries fall anywhere.
// Invariants checked on every sample: finite numbers, the raw record kept.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "leafdig/devices/codecs/calipers.hpp"
#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/codecs/line_digitizer.hpp"
#include "leafdig/devices/codecs/microscribe.hpp"
#include "leafdig/devices/codecs/polhemus.hpp"

namespace dev = leafdig::devices;

namespace {

void check(const std::vector<dev::StylusSample>& out) {
  for (const auto& s : out) {
    for (double v : s.positionMm)
      if (!std::isfinite(v)) std::abort();
    if (s.raw.empty()) std::abort();
  }
}
void check(const std::vector<dev::CaliperReading>& out) {
  for (const auto& r : out)
    if (!std::isfinite(r.valueMm) || r.raw.empty() || (r.unit != "mm" && r.unit != "in")) std::abort();
}

template <class Fn>
void chunked(const std::uint8_t* data, std::size_t size, Fn fn) {
  if (size == 0) return;
  const std::size_t step = 1 + data[0] % 64;
  for (std::size_t i = 1; i < size; i += step) fn(std::span<const std::uint8_t>(data + i, std::min(step, size - i)));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace std::string_literals;
  const std::string codec = LEAFDIG_FUZZ_CODEC;
  if (codec == "fastrak") {
    for (bool binary : {false, true}) {
      dev::fastrak::DecoderState st;
      st.format.items = {2, 4, 11, 16, 1};
      st.format.binary = binary;
      std::vector<dev::StylusSample> out;
      chunked(data, size, [&](auto b) { dev::fastrak::decode(st, b, out); });
      check(out);
    }
  } else if (codec == "polhemus") {
    for (bool binary : {false, true}) {
      dev::polhemus::DecoderState st;
      st.format.binary = binary;
      st.format.model = size % 2 ? dev::polhemus::Model::Liberty : dev::polhemus::Model::Patriot;
      st.format.items = {2, 5, 7, 8, 9, 10, 11, 0};
      std::vector<dev::StylusSample> out;
      chunked(data, size, [&](auto b) { dev::polhemus::decode(st, b, out); });
      check(out);
    }
  } else if (codec == "microscribe") {
    dev::microscribe::DecoderState st;
    st.arm = dev::microscribe::referenceArm();
    std::vector<dev::StylusSample> out;
    chunked(data, size, [&](auto b) { dev::microscribe::decode(st, b, out); });
    check(out);
    dev::microscribe::Arm arm;
    if (size >= 36) (void)dev::microscribe::decodeDhParams(std::span<const std::uint8_t>(data, 36), arm);
  } else if (codec == "line") {
    static const auto tokens =
        dev::line::parseConfig(R"({"fields": {"mode": "tokens", "x": 0, "y": 1, "z": 2, "button": 3}})");
    static const auto columns = dev::line::parseConfig(
        R"({"framing": {"terminator": "\n", "sync": "0"}, "fields": {"mode": "columns", "x": [2,7], "y": [9,7], "z": [16,7]}})");
    for (const auto* cfg : {&tokens, &columns}) {
      dev::line::DecoderState st;
      st.config = *cfg;
      std::vector<dev::StylusSample> out;
      chunked(data, size, [&](auto b) { dev::line::decode(st, b, out); });
      check(out);
    }
  } else if (codec == "hid") {
    dev::calipers::HidKeyboardState st;
    st.reportId = size % 2 == 1;
    std::vector<dev::CaliperReading> out;
    for (std::size_t i = 0; i + 8 <= size; i += 8)
      dev::calipers::decodeHidReport(st, std::span<const std::uint8_t>(data + i, 8), out);
    check(out);
  } else if (codec == "mitutoyo") {
    dev::calipers::MitutoyoState st;
    st.unit = "auto";
    std::vector<dev::CaliperReading> out;
    chunked(data, size, [&](auto b) { dev::calipers::decodeMitutoyo(st, b, out); });
    check(out);
  } else if (codec == "uwave") {
    dev::calipers::UWaveState st;
    std::vector<dev::CaliperReading> out;
    chunked(data, size, [&](auto b) { dev::calipers::decodeUWave(st, b, out); });
    check(out);
  } else if (codec == "digimatic") {
    std::vector<std::uint8_t> nibbles;
    for (std::size_t i = 0; i < size; ++i) nibbles.push_back(data[i] & 0x0f);
    for (std::size_t i = 0; i + 13 <= nibbles.size(); i += 13)
      if (auto r = dev::calipers::decodeDigimatic(std::span<const std::uint8_t>(nibbles.data() + i, 13))) check({*r});
    std::vector<std::uint8_t> bits;
    for (std::size_t i = 0; i < size && bits.size() < 52; ++i) bits.push_back(data[i] & 1);
    (void)dev::calipers::digimaticNibbles(bits);
  } else if (codec == "sylvac") {
    dev::calipers::SylvacState st;
    std::vector<dev::CaliperReading> out;
    chunked(data, size, [&](auto b) { dev::calipers::decodeSylvac(st, b, out); });
    check(out);
  } else {
    std::abort();
  }
  return 0;
}
