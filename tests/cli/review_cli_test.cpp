// The curator's record through the command line (issue 49): every decision and correction of a
// session — who, when, why, and for a correction the item with its value before and after and
// how far a point moved — in `sessions show` (text and --json) and the last decision in
// `sessions list --json`; `sessions list`'s filters. On a copy of the leaf and the plant of
// tests/data/legacy/ (complete captures).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

using nlohmann::json;

class ReviewCli : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    file_ = dir_ / "station.sqlite";
    fs::copy_file(std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/legacy/station-schema2.sqlite", file_);
  }
  std::string db() const { return " --db " + quote(file_); }
  json showJson(int id) {
    const Result r = leafdig("sessions show " + std::to_string(id) + " --json" + db());
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return json::parse(r.out);
  }
  std::vector<int> listed(const std::string& filters) {
    const Result r = leafdig("sessions list --json" + filters + db());
    EXPECT_EQ(r.exitCode, 0) << filters << "\n" << r.err;
    std::vector<int> ids;
    for (const json& s : json::parse(r.out)) ids.push_back(s.at("id").get<int>());
    return ids;
  }
  fs::path file_;
};

TEST_F(ReviewCli, EveryDecisionAndCorrectionIsShownWithWhoWhenWhyAndWhatItChanged) {
  const json leaf = showJson(1);
  EXPECT_TRUE(leaf.at("history").empty());
  const json& marker = leaf.at("markers").at(5);
  const int row = marker.at("row"), col = marker.at("col");
  const std::vector<double> from = marker.at("position_mm");
  const std::string to =
      std::to_string(from[0]) + "," + std::to_string(from[1] + 3.0) + "," + std::to_string(from[2] + 4.0);  // 5 mm away
  ASSERT_EQ(leafdig("sessions correct 1 --what marker --row " + std::to_string(row) + " --col " + std::to_string(col) +
                    " --position " + to + " --who carla --why 'the stylus slipped'" + db())
                .exitCode,
            0);
  ASSERT_EQ(
      leafdig("sessions correct 1 --what midrib_thickness --row 1 --col 4 --value 1.25 --who carla --why misread" +
              db())
          .exitCode,
      0);
  // Files of a session nobody approved say so (stderr; --json gives the status).
  const Result early = leafdig("sessions export 1 --format csv --out " + quote(dir_ / "early") + db());
  ASSERT_EQ(early.exitCode, 0) << early.err;
  EXPECT_NE(early.err.find("warning: session 1 is complete, not approved by a curator"), std::string::npos)
      << early.err;
  const Result earlyJson = leafdig("sessions export 1 --json --format csv --out " + quote(dir_ / "early") + db());
  EXPECT_EQ(json::parse(earlyJson.out).at("status"), "complete");
  ASSERT_EQ(leafdig("sessions approve 1 --who carla --why 'checked against the photos'" + db()).exitCode, 0);
  const Result late = leafdig("sessions export 1 --format csv --out " + quote(dir_ / "late") + db());
  ASSERT_EQ(late.exitCode, 0) << late.err;
  EXPECT_EQ(late.err.find("warning"), std::string::npos) << late.err;

  const json history = showJson(1).at("history");
  ASSERT_EQ(history.size(), 3u) << history.dump();
  EXPECT_EQ(history[0].at("action"), "corrected");
  EXPECT_EQ(history[0].at("what"), "marker");
  EXPECT_EQ(history[0].at("row"), row);
  EXPECT_EQ(history[0].at("col"), col);
  EXPECT_EQ(history[0].at("from").at("position_mm").get<std::vector<double>>(), from);
  EXPECT_NEAR(history[0].at("moved_mm").get<double>(), 5.0, 1e-5);
  EXPECT_EQ(history[0].at("who"), "carla");
  EXPECT_EQ(history[0].at("why"), "the stylus slipped");
  EXPECT_EQ(history[1].at("to"), (json{{"value_mm", 1.25}}));
  EXPECT_TRUE(history[1].at("from").contains("value_mm"));
  EXPECT_FALSE(history[1].contains("moved_mm"));
  EXPECT_EQ(history[2].at("action"), "approved");
  EXPECT_EQ(history[2].at("why"), "checked against the photos");
  EXPECT_EQ(history[2].at("utc").get<std::string>().size(), 24u);  // 2026-11-28T10:00:00.000Z
  EXPECT_LT(history[0].at("seq").get<int>(), history[2].at("seq").get<int>());

  const Result text = leafdig("sessions show 1" + db());
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("  corrected marker row " + std::to_string(row) + " col " + std::to_string(col) + ": ("),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("mm, moved 5.0 mm, by carla at "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(" → 1.250 mm, by carla at "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("  approved by carla at " + history[2].at("utc").get<std::string>()), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find(": checked against the photos\n"), std::string::npos) << text.out;

  // The plant: a correction of its own item, then a rejection; the list shows each last decision.
  ASSERT_EQ(
      leafdig("sessions correct 2 --what collar_diameter --value 9.5 --who dana --why re-measured" + db()).exitCode, 0);
  ASSERT_EQ(leafdig("sessions reject 2 --who dana --why 'node 3 was skipped'" + db()).exitCode, 0);
  const Result rejected = leafdig("sessions export 2 --format csv --out " + quote(dir_ / "plant") + db());
  ASSERT_EQ(rejected.exitCode, 0) << rejected.err;
  EXPECT_NE(rejected.err.find("warning: session 2 is rejected, not approved"), std::string::npos) << rejected.err;
  const json plant = showJson(2).at("history");
  ASSERT_EQ(plant.size(), 2u) << plant.dump();
  EXPECT_EQ(plant[0].at("what"), "collar_diameter");
  EXPECT_EQ(plant[0].at("to"), (json{{"value_mm", 9.5}}));
  EXPECT_EQ(plant[1].at("action"), "rejected");
  const Result plantText = leafdig("sessions show 2" + db());
  EXPECT_NE(plantText.out.find("  rejected by dana at "), std::string::npos) << plantText.out;
  EXPECT_NE(plantText.out.find("  corrected collar_diameter: "), std::string::npos) << plantText.out;

  const json list = json::parse(leafdig("sessions list --json" + db()).out);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].at("decision").at("action"), "approved");
  EXPECT_EQ(list[0].at("decision").at("who"), "carla");
  EXPECT_EQ(list[0].at("decision").at("why"), "checked against the photos");
  EXPECT_EQ(list[1].at("decision").at("action"), "rejected");
}

// A decision can be reopened by a curator with a reason (issue 49): the session is complete
// again, corrections and a new decision follow, the history keeps all of it in order, and what
// may not be reopened is refused in words, nothing written.
TEST_F(ReviewCli, ACuratorReopensADecisionWithAReasonAndDecidesAgain) {
  // Only a decided session is reopened, and never without a reason.
  const Result early = leafdig("sessions reopen 1 --who carla --why 'too early'" + db());
  EXPECT_NE(early.exitCode, 0);
  EXPECT_NE(early.err.find("session 1 is complete: only an approved or rejected session is reopened"),
            std::string::npos)
      << early.err;
  ASSERT_EQ(leafdig("sessions approve 1 --who carla --why 'looked fine'" + db()).exitCode, 0);
  const Result noWhy = leafdig("sessions reopen 1 --who dana" + db());
  EXPECT_NE(noWhy.exitCode, 0);
  EXPECT_NE(noWhy.err.find("--why"), std::string::npos) << noWhy.err;
  const Result blankWhy = leafdig("sessions reopen 1 --who dana --why '  '" + db());
  EXPECT_NE(blankWhy.exitCode, 0);
  EXPECT_NE(blankWhy.err.find("say why the session is reopened"), std::string::npos) << blankWhy.err;
  EXPECT_EQ(showJson(1).at("history").size(), 1u);  // nothing written by the refusals
  EXPECT_EQ(showJson(1).at("status"), "approved");
  // Approved sessions take no correction until reopened.
  const std::string correction =
      "sessions correct 1 --what midrib_thickness --row 1 --col 4 --value 1.25 --who dana --why misread" + db();
  EXPECT_NE(leafdig(correction).exitCode, 0);

  const Result reopened = leafdig("sessions reopen 1 --json --who dana --why 'the midrib of row 1 was misread'" + db());
  ASSERT_EQ(reopened.exitCode, 0) << reopened.err;
  const json r = json::parse(reopened.out);
  EXPECT_EQ(r.at("status"), "complete");
  EXPECT_EQ(r.at("reopens"), "approved");
  EXPECT_EQ(showJson(1).at("status"), "complete");
  // Complete again: no decision stands, the list says so; a second reopening is refused.
  const json list = json::parse(leafdig("sessions list --json" + db()).out);
  EXPECT_TRUE(list[0].at("decision").is_null()) << list[0].dump();
  EXPECT_EQ(listed(" --status complete"), (std::vector<int>{1, 2}));
  EXPECT_NE(leafdig("sessions reopen 1 --who dana --why again" + db()).exitCode, 0);
  ASSERT_EQ(leafdig(correction).exitCode, 0);
  ASSERT_EQ(leafdig("sessions reject 1 --who dana --why 'row 3 is missing its vein'" + db()).exitCode, 0);

  const json history = showJson(1).at("history");
  ASSERT_EQ(history.size(), 4u) << history.dump();
  EXPECT_EQ(history[0].at("action"), "approved");
  EXPECT_EQ(history[1].at("action"), "reopened");
  EXPECT_EQ(history[1].at("reopens"), "approved");
  EXPECT_EQ(history[1].at("who"), "dana");
  EXPECT_EQ(history[1].at("why"), "the midrib of row 1 was misread");
  EXPECT_EQ(history[2].at("action"), "corrected");
  EXPECT_EQ(history[3].at("action"), "rejected");
  const Result text = leafdig("sessions show 1" + db());
  EXPECT_NE(text.out.find("  reopened (was approved) by dana at "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(": the midrib of row 1 was misread\n"), std::string::npos) << text.out;
  const json after = json::parse(leafdig("sessions list --json" + db()).out);
  EXPECT_EQ(after[0].at("decision").at("action"), "rejected");
  // A rejection is reopened the same way; the chain still verifies.
  ASSERT_EQ(leafdig("sessions reopen 1 --who carla --why 'the vein was there after all'" + db()).exitCode, 0);
  EXPECT_EQ(showJson(1).at("history").back().at("reopens"), "rejected");
  EXPECT_EQ(leafdig("sessions verify 1" + db()).exitCode, 0);
}

// A correction that would move a point further than 20 mm (a typo, another point) is refused
// in words saying how far, until the curator confirms it; nothing is written before.
TEST_F(ReviewCli, AFarMoveIsShownAndNeedsConfirming) {
  const json tip = showJson(1).at("tip");
  const std::string far = std::to_string(tip[0].get<double>() + 612.0) + "," + std::to_string(tip[1].get<double>()) +
                          "," + std::to_string(tip[2].get<double>());
  const int events = showJson(1).at("events");
  const Result refused = leafdig("sessions correct 1 --what tip --position " + far + " --who carla --why typo" + db());
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_NE(refused.err.find("the tip would move 612.0 mm, more than the 20.0 mm a correction moves unconfirmed"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(showJson(1).at("events"), events);
  // A dry run shows the move and what it does to the leaf, and writes nothing.
  const Result dry =
      leafdig("sessions correct 1 --what tip --position " + far + " --dry-run --json --who carla --why typo" + db());
  ASSERT_EQ(dry.exitCode, 0) << dry.err;
  const json effect = json::parse(dry.out);
  EXPECT_EQ(effect.at("dry_run"), true);
  EXPECT_NEAR(effect.at("moved_mm").get<double>(), 612.0, 1e-4);
  EXPECT_EQ(effect.at("needs_confirm"), true);
  bool area = false;
  for (const json& ch : effect.at("changes"))
    if (ch.at("what") == "blade area_mm2") {
      area = true;
      EXPECT_GT(ch.at("after").get<double>(), ch.at("before").get<double>() * 1.05) << "the tip pulled 612 mm out";
    }
  EXPECT_TRUE(area) << dry.out;
  const Result dryText =
      leafdig("sessions correct 1 --what tip --position " + far + " --dry-run --who carla --why typo" + db());
  EXPECT_NE(dryText.out.find("would be corrected, moving 612.0 mm; nothing written (--dry-run)"), std::string::npos)
      << dryText.out;
  EXPECT_NE(dryText.out.find("  blade area_mm2: "), std::string::npos) << dryText.out;
  EXPECT_NE(dryText.out.find("writing it needs --confirm"), std::string::npos) << dryText.out;
  EXPECT_EQ(showJson(1).at("events"), events);
  // A leaf's points are the digitizer's: the plant frame is refused, in words.
  const Result plantFrame =
      leafdig("sessions correct 1 --what tip --position 1,2,3 --frame plant --who carla --why x" + db());
  EXPECT_EQ(plantFrame.exitCode, 2);
  EXPECT_NE(plantFrame.err.find("captured one leaf: its points are corrected in the digitizer's frame"),
            std::string::npos)
      << plantFrame.err;
  EXPECT_EQ(showJson(1).at("events"), events);
  // A lower limit of one's own, and a confirmed move; the output says how far the point went.
  const std::string near = std::to_string(tip[0].get<double>() + 6.0) + "," + std::to_string(tip[1].get<double>()) +
                           "," + std::to_string(tip[2].get<double>());
  EXPECT_EQ(
      leafdig("sessions correct 1 --what tip --position " + near + " --confirm-above 5 --who carla --why x" + db())
          .exitCode,
      2);
  const Result moved =
      leafdig("sessions correct 1 --what tip --position " + near + " --who carla --why slipped" + db());
  ASSERT_EQ(moved.exitCode, 0) << moved.err;
  EXPECT_NE(moved.out.find(", moved 6.0 mm"), std::string::npos) << moved.out;
  const Result confirmed =
      leafdig("sessions correct 1 --what tip --position " + far + " --confirm --json --who carla --why typo" + db());
  ASSERT_EQ(confirmed.exitCode, 0) << confirmed.err;
  EXPECT_NEAR(json::parse(confirmed.out).at("moved_mm").get<double>(), 606.0, 1e-4);
}

TEST_F(ReviewCli, SessionsAreListedByStatusKindPlantStationAndDay) {
  const json all = json::parse(leafdig("sessions list --json" + db()).out);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_TRUE(all[0].at("decision").is_null());
  const std::string leafPlant = all[0].at("plant");
  const std::string station = all[0].at("station");
  const std::string day = all[0].at("created_utc").get<std::string>().substr(0, 10);
  EXPECT_EQ(listed(""), (std::vector<int>{1, 2}));
  EXPECT_EQ(listed(" --kind plant"), (std::vector<int>{2}));
  EXPECT_EQ(listed(" --kind leaf"), (std::vector<int>{1}));
  EXPECT_EQ(listed(" --status complete"), (std::vector<int>{1, 2}));
  EXPECT_EQ(listed(" --status approved"), (std::vector<int>{}));
  EXPECT_EQ(listed(" --plant " + quote(leafPlant) + " --kind leaf"), (std::vector<int>{1}));
  EXPECT_EQ(listed(" --station " + quote(station)), (std::vector<int>{1, 2}));
  EXPECT_EQ(listed(" --station elsewhere"), (std::vector<int>{}));
  EXPECT_EQ(listed(" --since " + day), (std::vector<int>{1, 2}));
  EXPECT_EQ(listed(" --since 2099-01-01"), (std::vector<int>{}));
  ASSERT_EQ(leafdig("sessions approve 1 --who carla" + db()).exitCode, 0);
  EXPECT_EQ(listed(" --status approved"), (std::vector<int>{1}));
  const Result none = leafdig("sessions list --since 2099-01-01" + db());
  EXPECT_EQ(none.exitCode, 0);
  EXPECT_NE(none.out.find("(no sessions that match in "), std::string::npos) << none.out;
  // Bad filters are refused in words, exit 2.
  for (const char* bad : {" --since yesterday", " --status done", " --kind tree"}) {
    const Result r = leafdig(std::string("sessions list") + bad + db());
    EXPECT_EQ(r.exitCode, 2) << bad;
    EXPECT_FALSE(r.err.empty()) << bad;
  }
}

// A plant session's `sessions show` is the plant as surveyed (issue 49: it was three counting
// lines): every node with its height, internode and stem diameter, every leaf with its kind,
// angles, chord and area — the survey `plant measure` makes of the session's exported markers,
// one definition.
TEST_F(ReviewCli, APlantSessionIsShownAsItsSurvey) {
  const json shown = showJson(2);
  ASSERT_TRUE(shown.at("survey").is_object()) << shown.dump();
  EXPECT_EQ(shown.at("survey_problem"), "");
  const json& survey = shown.at("survey");
  EXPECT_EQ(survey.at("nodes").size(), shown.at("nodes").get<std::size_t>());
  ASSERT_EQ(leafdig("sessions export 2 --format markers --out " + quote(dir_ / "plant") + db()).exitCode, 0);
  const Result measured = leafdig("plant measure --json " + quote(dir_ / "plant" / "session-2.plant-markers.json"));
  ASSERT_EQ(measured.exitCode, 0) << measured.err;
  EXPECT_EQ(survey, json::parse(measured.out));
  int withArea = 0;
  for (const json& leaf : survey.at("leaves"))
    if (leaf.contains("area_mm2") && leaf.at("area_mm2").is_number()) ++withArea;
  EXPECT_GT(withArea, 0) << survey.dump();

  const Result text = leafdig("sessions show 2" + db());
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("  survey: plant "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("  node 1: height "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(" mm^2"), std::string::npos) << text.out;
}

// A long project or plant name never runs into the next column (it used to: the leaf column was
// 28 characters wide whatever it held, "plants/tobacco-p12-sucker/(plant)technician").
TEST_F(ReviewCli, TheListsColumnsAreAsWideAsTheirLongestName) {
  sqlite3* file = nullptr;
  ASSERT_EQ(sqlite3_open(file_.c_str(), &file), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(file, "UPDATE projects SET name = 'tobacco-nitrogen-trial-2026-greenhouse-' || id", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(file);
  const Result r = leafdig("sessions list" + db());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, line;
  ASSERT_TRUE(std::getline(lines, header));
  const std::size_t operatorAt = header.find("operator"), eventsAt = header.find("events");
  ASSERT_NE(operatorAt, std::string::npos) << r.out;
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    ASSERT_GT(line.size(), eventsAt) << r.out;
    EXPECT_NE(line.find("tobacco-nitrogen-trial-2026-greenhouse-"), std::string::npos) << line;
    // The operator's name begins under its header, after at least two spaces.
    EXPECT_EQ(line.substr(operatorAt - 2, 2), "  ") << r.out;
    EXPECT_NE(line[operatorAt], ' ') << r.out;
    EXPECT_NE(line[eventsAt], ' ') << r.out;
  }
  EXPECT_EQ(rows, 2) << r.out;
}

}  // namespace
