// The fault matrix: every fault kind × 20 seeded runs of a FASTRAK emulator against the
// driver. The bar: nothing corrupt becomes a sample (a corrupt record is dropped and
// counted), the link recovers by itself, and every state change is reported.
// And the long stream: ten minutes of 120 Hz records as fast as the pty allows, none lost.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "device_test_support.hpp"
#include "leafdig/devices/codecs/fastrak.hpp"
#include "leafdig/devices/links/links.hpp"

namespace dev = leafdig::devices;
using dev::testing::Collector;
using dev::testing::dist;
using namespace std::chrono_literals;

namespace {

struct FaultCase {
  const char* name;
  const char* spec;  // per-record probabilities at 1000 records/s
  bool binary;
};

void PrintTo(const FaultCase& c, std::ostream* os) {
  *os << c.name;
}

class FaultMatrix : public ::testing::TestWithParam<FaultCase> {};

TEST_P(FaultMatrix, NoCorruptSampleAndTheLinkRecovers) {
  const FaultCase c = GetParam();
  constexpr int kSeeds = 20;
  std::uint64_t totalFaults = 0, totalDelivered = 0, valueFlipsDelivered = 0;
  double worstFlipErrorMm = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    dev::sim::EmulatorOptions eo;
    eo.rateHz = 1000;
    eo.faults = dev::sim::FaultPlan::parse(std::string(c.spec) + ",seed=" + std::to_string(seed));
    auto emu = dev::sim::makeFastrak(dev::testing::quickStylus(static_cast<std::uint64_t>(seed)), eo);
    emu->start();
    dev::DigitizerConfig cfg;
    cfg.port = emu->path();
    cfg.binary = c.binary;
    Collector col;
    dev::Driver driver(dev::makeDigitizerLink(cfg), col.callbacks());
    driver.start();
    // Run until a fault has happened and 200 more samples arrived after it (recovery). The
    // deadline only bounds a link that never recovers: it is not a speed requirement (under
    // TSan on a loaded machine every stall costs a second of silence and a re-initialisation,
    // and 12 s once ran out while the link was recovering).
    std::size_t mark = 0;
    bool faulted = false;
    const auto deadline = std::chrono::steady_clock::now() + 90s;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto log = emu->faultLog();
      const std::uint64_t n = log.garbage + log.bitflips + log.truncated + log.stalls + log.resets + log.unplugs +
                              log.statusLetters + log.garbledBytes;
      if (!faulted && n > 0) {
        faulted = true;
        // Recovery is 200 samples past every record the device had sent by then: on a loaded
        // machine the driver may still be reading records from before the fault, and 200 of
        // those would end the run before the link has shown it noticed (a reset's silence).
        mark = std::max<std::size_t>(col.stylusCount(), emu->recordsSent());
      }
      if (faulted && col.stylusCount() >= mark + 200) break;
      std::this_thread::sleep_for(10ms);
    }
    driver.stop();
    emu->stop();
    ASSERT_TRUE(faulted) << "the fault never happened";
    ASSERT_GE(col.stylusCount(), mark + 200) << "the link did not recover:\n" << col.statusLog();

    // Every delivered sample is a record the device sent, unaltered, or (bit flips that still
    // form a valid record: FASTRAK has no checksum) within the spike filter's reach of it.
    const auto sent = emu->sentRecords();
    std::map<std::string, const dev::sim::SentRecord*> intact;
    for (const auto& r : sent)
      if (r.sent.size() >= r.original.size() &&
          r.sent.compare(r.sent.size() - r.original.size(), r.original.size(), r.original) == 0)
        intact[r.original] = &r;
    std::lock_guard lock(col.mutex);
    for (const auto& s : col.stylus) {
      if (intact.count(s.raw)) continue;
      const dev::sim::SentRecord* from = nullptr;
      for (const auto& r : sent)
        if (r.sent.find(s.raw) != std::string::npos) from = &r;
      ASSERT_NE(from, nullptr) << "a sample from bytes the device never sent: " << dev::printableRaw(s.raw);
      ASSERT_EQ(std::string(c.name).rfind("BitFlip", 0), 0u)
          << "an altered record was delivered: " << dev::printableRaw(s.raw);
      ++valueFlipsDelivered;
      worstFlipErrorMm = std::max(worstFlipErrorMm, dist(s.positionMm, from->truthMm));
      EXPECT_LT(dist(s.positionMm, from->truthMm), 2.6) << dev::printableRaw(s.raw);
    }
    // No phantom presses: every run of pressed samples contains a record really pressed.
    for (std::size_t i = 0; i < col.stylus.size();) {
      if (!col.stylus[i].button) {
        ++i;
        continue;
      }
      bool real = false;
      std::size_t j = i;
      for (; j < col.stylus.size() && col.stylus[j].button; ++j)
        if (auto it = intact.find(col.stylus[j].raw); it != intact.end() && it->second->button) real = true;
      // the debounced press may outlast the last pressed record by one sample
      if (j < col.stylus.size()) {
        if (auto it = intact.find(col.stylus[j].raw); it != intact.end() && it->second->button) real = true;
      }
      EXPECT_TRUE(real) << "a phantom button press at sample " << i;
      i = j;
    }
    // Every fault is visible: counted by the codec, or reported as a state change.
    const auto log = emu->faultLog();
    const auto st = driver.status();
    totalFaults +=
        log.garbage + log.bitflips + log.truncated + log.stalls + log.resets + log.unplugs + log.statusLetters;
    totalDelivered += col.stylus.size();
    if (log.garbage + log.truncated > 0) {
      EXPECT_GT(st.stats.dropped + st.stats.discardedBytes, 0u);
    }
    if (log.unplugs > 0) {
      EXPECT_TRUE(col.sawState(dev::LinkState::Disconnected)) << col.statusLog();
      EXPECT_GE(st.reconnects, 1);
    }
    if (log.stalls + log.resets > 0) {
      EXPECT_TRUE(col.sawState(dev::LinkState::Warning, "no data")) << col.statusLog();
    }
    if (log.statusLetters > 0) {
      EXPECT_TRUE(col.sawState(dev::LinkState::Warning, "status 'x'")) << col.statusLog();
      EXPECT_GT(st.stats.statusWarnings, 0u);
    }
    if (log.garbledBytes > 0) {
      EXPECT_TRUE(col.sawState(dev::LinkState::Warning, "--baud 9600")) << col.statusLog();
    }
    EXPECT_TRUE(col.sawState(dev::LinkState::Streaming));
  }
  RecordProperty("faults", std::to_string(totalFaults));
  RecordProperty("delivered", std::to_string(totalDelivered));
  RecordProperty("bitflipsDeliveredWithinFilter", std::to_string(valueFlipsDelivered));
  std::printf(
      "%s: %d runs, %llu faults injected, %llu samples delivered, %llu value-altering bit flips passed "
      "(worst %.3f mm)\n",
      c.name, kSeeds, static_cast<unsigned long long>(totalFaults), static_cast<unsigned long long>(totalDelivered),
      static_cast<unsigned long long>(valueFlipsDelivered), worstFlipErrorMm);
}

// Stall: 2 s against the driver's 1 s stall timeout. The silence the driver sees is the stall less
// how far its reading lagged behind the device when the stall began: 1.4 s (0.4 s of margin)
// failed once under ASan with the suite and a compiler beside it (seed 7: no "no data"), as
// 1.1 s had before; a second of margin costs 20 runs 12 s.
INSTANTIATE_TEST_SUITE_P(
    Faults, FaultMatrix,
    ::testing::Values(FaultCase{"Garbage", "garbage=0.02", false}, FaultCase{"BitFlipAscii", "bitflip=0.02", false},
                      FaultCase{"BitFlipBinary", "bitflip=0.02", true}, FaultCase{"Truncate", "truncate=0.02", false},
                      FaultCase{"TruncateBinary", "truncate=0.02", true}, FaultCase{"Stall", "stall=0.003:2", false},
                      FaultCase{"Reset", "reset=0.002", false}, FaultCase{"Unplug", "unplug=0.002:0.3", false},
                      FaultCase{"StatusLetter", "status=0.02:x", false}, FaultCase{"WrongBaud", "baud=9600", false}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(LongStream, TenMinutesAt120HzWithoutLosingARecord) {
  constexpr std::uint64_t kRecords = 10 * 60 * 120;
  dev::sim::EmulatorOptions eo;
  eo.burst = true;
  eo.burstRecords = kRecords;
  auto emu = dev::sim::makeFastrak(dev::testing::quickStylus(), eo);
  emu->start();
  dev::DigitizerConfig cfg;
  cfg.port = emu->path();
  std::atomic<std::uint64_t> delivered{0};
  dev::DriverOptions o;
  o.filterStylus = false;  // count what the link and codec deliver
  const auto t0 = std::chrono::steady_clock::now();
  dev::Driver driver(dev::makeDigitizerLink(cfg),
                     {[&](const dev::DeviceEvent&) { ++delivered; },
                      [&](const dev::DeviceStatus& s) {
                        if (std::getenv("LEAFDIG_TRACE"))
                          std::fprintf(stderr, "%.3f %s %s %llu\n",
                                       std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                                       dev::toString(s.state), s.message.c_str(),
                                       static_cast<unsigned long long>(delivered.load()));
                      }},
                     o);
  driver.start();
  while (delivered < kRecords && std::chrono::steady_clock::now() - t0 < 240s) std::this_thread::sleep_for(20ms);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  driver.stop();
  const auto st = driver.status();
  EXPECT_EQ(delivered.load(), kRecords);
  EXPECT_EQ(emu->recordsSent(), kRecords);
  EXPECT_EQ(st.stats.dropped, 0u);
  EXPECT_EQ(st.stats.discardedBytes, 0u);
  EXPECT_EQ(st.reconnects, 0);
  std::printf("long stream: %llu records in %.1f s (%.0f records/s, %.1fx real time)\n",
              static_cast<unsigned long long>(delivered.load()), seconds, delivered / seconds, 600.0 / seconds);
}

}  // namespace
