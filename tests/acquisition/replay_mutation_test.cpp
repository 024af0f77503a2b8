// Replay fuzzed (issue 47, 18): a leaf's and a plant's real event logs (the legacy station file,
// tests/data/legacy/), mutated some two thousand ways — a number, a row or column, a key taken out
// or added, a kind changed, an event dropped, repeated, swapped or the log cut — and replayed,
// then made into what an export makes (the leaf's markers and model, the plant's survey).
// Each must either work or be refused in words (SessionError, model::InputError,
// std::invalid_argument: what the CLI reports as exit 2 with its message); a crash, a
// sanitizer's finding or another exception (json's type_error, out_of_range: "internal error,
// report it") fails. Deterministic: the seeds are fixed, so a failure names its mutation.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/preview.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

namespace acq = leafdig::acquisition;
namespace db = leafdig::db;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Logs {
  db::SessionInfo leaf, plant;
  std::vector<db::Event> leafEvents, plantEvents;
};

Logs legacyLogs() {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-mutate-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(fs::path(LEAFDIG_SOURCE_DIR) / "tests/data/legacy/station-schema2.sqlite", dir / "s.sqlite");
  Logs out;
  {
    db::Store store((dir / "s.sqlite").string());
    out.leaf = *store.session(1);
    out.plant = *store.session(2);
    out.leafEvents = store.events(1);
    out.plantEvents = store.events(2);
  }
  fs::remove_all(dir);
  return out;
}

// Every value of a JSON document, by pointer, so that one can be picked and replaced.
void valuesOf(const json& j, const json::json_pointer& at, std::vector<json::json_pointer>& out) {
  out.push_back(at);
  if (j.is_object())
    for (const auto& [k, v] : j.items()) valuesOf(v, at / k, out);
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) valuesOf(j[i], at / i, out);
}

const std::vector<json>& oddValues() {
  static const std::vector<json> values{0,
                                        -1,
                                        1,
                                        2,
                                        7,
                                        8,
                                        1000,
                                        1001,
                                        -2.5,
                                        1e15,
                                        -1e15,
                                        9.9e14,
                                        "",
                                        "x",
                                        "+",
                                        "marker",
                                        "tip",
                                        true,
                                        nullptr,
                                        json::array(),
                                        json::object(),
                                        json::array({1, 2}),
                                        json::array({1e15, 0, 0})};
  return values;
}

// One mutation of `events`, described in `what`.
std::vector<db::Event> mutate(std::vector<db::Event> events, std::mt19937& rng, std::string& what) {
  const auto pick = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  const std::size_t i = pick(events.size());
  db::Event& e = events[i];
  switch (pick(8)) {
    case 0:
    case 1: {  // a value of the payload replaced
      json p = json::parse(e.payloadJson, nullptr, false);
      if (p.is_discarded()) break;
      std::vector<json::json_pointer> at;
      valuesOf(p, json::json_pointer(), at);
      const auto& where = at[pick(at.size())];
      const json value = oddValues()[pick(oddValues().size())];
      what = "event " + std::to_string(e.seq) + " (" + e.kind + ") " + where.to_string() + " = " + value.dump();
      if (where.empty())
        p = value;
      else
        p[where] = value;
      e.payloadJson = p.dump();
      break;
    }
    case 2: {  // a key taken out, or one added
      json p = json::parse(e.payloadJson, nullptr, false);
      if (!p.is_object() || p.empty()) break;
      auto it = p.begin();
      std::advance(it, static_cast<std::ptrdiff_t>(pick(p.size())));
      if (pick(2) == 0) {
        what = "event " + std::to_string(e.seq) + " (" + e.kind + ") without " + it.key();
        p.erase(it);
      } else {
        what = "event " + std::to_string(e.seq) + " (" + e.kind + ") with an extra key";
        p["extra"] = 1;
      }
      e.payloadJson = p.dump();
      break;
    }
    case 3: {  // the kind of another event
      const std::string kind = events[pick(events.size())].kind;
      what = "event " + std::to_string(e.seq) + " (" + e.kind + ") as a " + kind;
      e.kind = kind;
      break;
    }
    case 4:
      what = "event " + std::to_string(e.seq) + " dropped";
      events.erase(events.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    case 5:
      what = "event " + std::to_string(e.seq) + " twice";
      events.insert(events.begin() + static_cast<std::ptrdiff_t>(i), events[i]);
      break;
    case 6:
      if (i + 1 < events.size()) {
        what = "events " + std::to_string(e.seq) + " and the next swapped";
        std::swap(events[i], events[i + 1]);
      }
      break;
    default:
      what = "the log cut after event " + std::to_string(e.seq);
      events.resize(i + 1);
      break;
  }
  return events;
}

// Replays a mutated log and makes what an export makes of it; "" when it worked or was
// refused in words, else what went wrong.
std::string replayAndBuild(const db::SessionInfo& info, const std::vector<db::Event>& events) {
  try {
    acq::requireReplays(info, events);
    if (info.kind == "plant") {
      const auto setup = acq::PlantCaptureSession::setupFromJson(info.settingsJson);
      const auto engine = acq::PlantCaptureSession::replay(setup, events);
      (void)leafdig::model::surveyPlant(engine.captured(info.plant));
    } else {
      const auto settings = acq::CaptureSession::settingsFromJson(info.settingsJson);
      const auto engine = acq::CaptureSession::replay(settings, events);
      (void)leafdig::model::buildLeafModel(acq::toMarkerSet(engine.items(), settings));
    }
    return "";
  } catch (const acq::SessionError&) {
    return "";
  } catch (const leafdig::model::InputError&) {
    return "";
  } catch (const std::invalid_argument&) {
    return "";
  } catch (const std::exception& e) {
    return std::string("not refused in words: ") + e.what();
  }
}

void mutateMany(const db::SessionInfo& info, const std::vector<db::Event>& events, unsigned seed, int count,
                int& refused) {
  std::mt19937 rng(seed);
  for (int n = 0; n < count; ++n) {
    std::string what = "nothing";
    const auto mutated = mutate(events, rng, what);
    const std::string problem = replayAndBuild(info, mutated);
    EXPECT_EQ(problem, "") << info.kind << " session, mutation " << n << ": " << what;
    try {
      acq::requireReplays(info, mutated);
    } catch (const std::exception&) {
      ++refused;
    }
  }
}

}  // namespace

TEST(ReplayMutation, TheOriginalLogsReplayAndBuild) {
  const Logs logs = legacyLogs();
  ASSERT_EQ(logs.leaf.kind, "leaf");
  ASSERT_EQ(logs.plant.kind, "plant");
  EXPECT_EQ(replayAndBuild(logs.leaf, logs.leafEvents), "");
  EXPECT_EQ(replayAndBuild(logs.plant, logs.plantEvents), "");
  EXPECT_NO_THROW(acq::requireReplays(logs.leaf, logs.leafEvents));
  EXPECT_NO_THROW(acq::requireReplays(logs.plant, logs.plantEvents));
}

TEST(ReplayMutation, AMutatedLeafLogReplaysOrIsRefusedInWords) {
  const Logs logs = legacyLogs();
  int refused = 0;
  mutateMany(logs.leaf, logs.leafEvents, 47, 1500, refused);
  // The mutations reach the replay's checks: many are refused (not all taken as harmless).
  EXPECT_GT(refused, 300);
}

TEST(ReplayMutation, AMutatedPlantLogReplaysOrIsRefusedInWords) {
  const Logs logs = legacyLogs();
  int refused = 0;
  mutateMany(logs.plant, logs.plantEvents, 18, 400, refused);  // a plant's replay and survey cost more
  EXPECT_GT(refused, 80);
}
