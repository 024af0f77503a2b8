// Decode throughput per codec, as a ratio to what a 115200-baud link can carry
// (11 520 bytes/s with 8N1 framing). Target: >= 1000x. Results: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "leafdig/devices/codecs/calipers.hpp"
#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/codecs/line_digitizer.hpp"
#include "leafdig/devices/codecs/microscribe.hpp"
#include "leafdig/devices/codecs/polhemus.hpp"

namespace dev = leafdig::devices;

namespace {

constexpr double kLinkBytesPerSecond = 115200.0 / 10.0;

dev::StylusSample sampleAt(int i) {
  dev::StylusSample s;
  s.positionMm = {10.0 + i % 97, -20.0 - i % 53, 3.0 + i % 7};
  s.orientationDeg = dev::Vec3{10.0, -45.0, 1.0 * (i % 90)};
  s.quaternion = std::array<double, 4>{1, 0, 0, 0};
  s.button = i % 50 < 10;
  return s;
}

std::vector<std::uint8_t> toBytes(const std::string& s) {
  return {s.begin(), s.end()};
}

template <class State, class Out, class Fn>
void run(benchmark::State& state, const std::vector<std::uint8_t>& stream, State init, Fn fn, std::size_t expected) {
  std::vector<Out> out;
  out.reserve(expected);
  for (auto _ : state) {
    State st = init;
    out.clear();
    // Feed as a serial driver does: reads of up to 4096 bytes.
    for (std::size_t i = 0; i < stream.size(); i += 4096)
      fn(st, std::span<const std::uint8_t>(stream.data() + i, std::min<std::size_t>(4096, stream.size() - i)), out);
    if (out.size() != expected) state.SkipWithError("wrong number of records decoded");
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * stream.size()));
  state.counters["x_link_115200"] = benchmark::Counter(static_cast<double>(stream.size()) / kLinkBytesPerSecond,
                                                       benchmark::Counter::kIsIterationInvariantRate);
}

void FastrakAscii(benchmark::State& state) {
  dev::fastrak::Format f;
  f.items = {2, 4, 16, 1};
  f.centimetres = true;
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::fastrak::encode(f, sampleAt(i));
  dev::fastrak::DecoderState init;
  init.format = f;
  run<dev::fastrak::DecoderState, dev::StylusSample>(state, toBytes(s), init, dev::fastrak::decode, 2000);
}
BENCHMARK(FastrakAscii);

void FastrakBinary(benchmark::State& state) {
  dev::fastrak::Format f;
  f.items = {2, 11, 16, 0};
  f.binary = true;
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::fastrak::encode(f, sampleAt(i));
  dev::fastrak::DecoderState init;
  init.format = f;
  run<dev::fastrak::DecoderState, dev::StylusSample>(state, toBytes(s), init, dev::fastrak::decode, 2000);
}
BENCHMARK(FastrakBinary);

void PatriotAscii(benchmark::State& state) {
  dev::polhemus::Format f;
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::polhemus::encode(f, sampleAt(i), static_cast<std::uint32_t>(i), 0);
  dev::polhemus::DecoderState init;
  init.format = f;
  run<dev::polhemus::DecoderState, dev::StylusSample>(state, toBytes(s), init, dev::polhemus::decode, 2000);
}
BENCHMARK(PatriotAscii);

void LibertyBinary(benchmark::State& state) {
  dev::polhemus::Format f;
  f.model = dev::polhemus::Model::Liberty;
  f.binary = true;
  f.items = {2, 7, 8, 10, 0};
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::polhemus::encode(f, sampleAt(i), static_cast<std::uint32_t>(i), 0);
  dev::polhemus::DecoderState init;
  init.format = f;
  run<dev::polhemus::DecoderState, dev::StylusSample>(state, toBytes(s), init, dev::polhemus::decode, 2000);
}
BENCHMARK(LibertyBinary);

void MicroScribe(benchmark::State& state) {
  std::vector<std::uint8_t> s;
  for (int i = 0; i < 2000; ++i) {
    dev::microscribe::Packet p;
    for (std::size_t k = 0; k < 6; ++k) p.counts[k] = (i * 37 + static_cast<int>(k) * 1000) % 16384;
    const auto b = dev::microscribe::encodePacket(p);
    s.insert(s.end(), b.begin(), b.end());
  }
  dev::microscribe::DecoderState init;
  init.arm = dev::microscribe::referenceArm();
  run<dev::microscribe::DecoderState, dev::StylusSample>(state, s, init, dev::microscribe::decode, 2000);
}
BENCHMARK(MicroScribe);

void LineTokens(benchmark::State& state) {
  std::string s;
  for (int i = 0; i < 2000; ++i) s += std::to_string(i % 97) + ".25, -" + std::to_string(i % 53) + ".5, 3.125, 0\r\n";
  dev::line::DecoderState init;
  init.config = dev::line::parseConfig(R"({"fields": {"mode": "tokens", "x": 0, "y": 1, "z": 2, "button": 3}})");
  run<dev::line::DecoderState, dev::StylusSample>(state, toBytes(s), init, dev::line::decode, 2000);
}
BENCHMARK(LineTokens);

void HidKeyboard(benchmark::State& state) {
  std::vector<std::uint8_t> s;
  for (int i = 0; i < 500; ++i)
    for (const auto& r : dev::calipers::encodeHidText("0." + std::to_string(100 + i % 800) + "\n"))
      s.insert(s.end(), r.begin(), r.end());
  std::vector<dev::CaliperReading> out;
  for (auto _ : state) {
    dev::calipers::HidKeyboardState st;
    out.clear();
    for (std::size_t i = 0; i + 8 <= s.size(); i += 8)
      dev::calipers::decodeHidReport(st, std::span<const std::uint8_t>(s.data() + i, 8), out);
    if (out.size() != 500) state.SkipWithError("wrong number of readings");
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * s.size()));
  state.counters["x_link_115200"] = benchmark::Counter(static_cast<double>(s.size()) / kLinkBytesPerSecond,
                                                       benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(HidKeyboard);

void MitutoyoAscii(benchmark::State& state) {
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::calipers::encodeMitutoyo(0.001 * i, 3);
  run<dev::calipers::MitutoyoState, dev::CaliperReading>(state, toBytes(s), {}, dev::calipers::decodeMitutoyo, 2000);
}
BENCHMARK(MitutoyoAscii);

void UWave(benchmark::State& state) {
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::calipers::encodeUWave(0.01 * i, "mm");
  run<dev::calipers::UWaveState, dev::CaliperReading>(state, toBytes(s), {}, dev::calipers::decodeUWave, 2000);
}
BENCHMARK(UWave);

void Sylvac(benchmark::State& state) {
  std::string s;
  for (int i = 0; i < 2000; ++i) s += dev::calipers::encodeSylvac(0.001 * i, 3);
  run<dev::calipers::SylvacState, dev::CaliperReading>(state, toBytes(s), {}, dev::calipers::decodeSylvac, 2000);
}
BENCHMARK(Sylvac);

void Digimatic(benchmark::State& state) {
  std::vector<std::array<std::uint8_t, 13>> frames;
  for (int i = 0; i < 2000; ++i) frames.push_back(dev::calipers::encodeDigimatic(0.001 * i, 3, false));
  for (auto _ : state) {
    double sum = 0;
    for (const auto& f : frames) sum += dev::calipers::decodeDigimatic(f)->valueMm;
    benchmark::DoNotOptimize(sum);
  }
  // On the wire a frame is 52 bits; against a 115200 baud link that is 6.5 bytes.
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * frames.size() * 13));
  state.counters["x_link_115200"] = benchmark::Counter(static_cast<double>(frames.size()) * 6.5 / kLinkBytesPerSecond,
                                                       benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(Digimatic);

}  // namespace
