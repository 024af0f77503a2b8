#include "leafdig/acquisition/protocol/items.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::acquisition {

static_assert(kMarkersPerRow == model::kMarkersPerRow);

bool isStylusItem(What w) {
  return w == What::Board || w == What::Tip || w == What::Marker || w == What::BoardAgain;
}

double distanceMm(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

const Item* findItem(const std::vector<Item>& items, What w, int row, int col) {
  for (const Item& i : items)
    if (i.what == w && i.row == row && i.col == col) return &i;
  return nullptr;
}

int completeRows(const std::vector<Item>& items) {
  // A row is complete when each of its seven columns holds a marker (not any seven markers).
  const auto complete = [&](int row) {
    std::array<bool, 7> held{};
    for (const Item& i : items)
      if (i.what == What::Marker && i.row == row && i.col >= 1 && i.col <= 7)
        held[static_cast<std::size_t>(i.col - 1)] = true;
    return std::all_of(held.begin(), held.end(), [](bool h) { return h; });
  };
  int r = 0;
  while (complete(r + 1)) ++r;
  return r;
}

namespace {

constexpr NameTable<What, 9> kWhatNames{{{What::Board, "board"},
                                         {What::Tip, "tip"},
                                         {What::Marker, "marker"},
                                         {What::MidribThickness, "midrib_thickness"},
                                         {What::VeinOriginThickness, "vein_origin_thickness"},
                                         {What::EdgeThickness, "edge_thickness"},
                                         {What::PointThickness, "point_thickness"},
                                         {What::BoardAgain, "board_again"},
                                         {What::Done, "done"}}};
// The items a technician can name: every word but "done", the end of the protocol.
constexpr auto kItemNames = [] {
  NameTable<What, kWhatNames.size() - 1> items{};
  for (std::size_t i = 0; i < items.size(); ++i) items[i] = kWhatNames[i];
  return items;
}();
static_assert(kWhatNames.back().first == What::Done);

}  // namespace

const char* toString(Order o) {
  return nameIn(kOrderNames, o);
}
Order orderFromString(const std::string& s) {
  return parseName(kOrderNames, s, "capture order");
}

const char* toString(What w) {
  return nameIn(kWhatNames, w);
}

What whatFromString(const std::string& s) {
  return parseName(kItemNames, s, "item");
}

std::string cutPressWords(std::int64_t heldNs) {
  char b[200];
  std::snprintf(b, sizeof b,
                "the digitizer connected again %.1f s into the press (a reset or an unplug cut it): the press was "
                "not taken; press again",
                static_cast<double>(heldNs) / 1e9);
  return b;
}

std::optional<PressEnd> StylusPress::take(const StylusInput& s, const Settings& settings) {
  std::optional<PressEnd> end;
  if (s.streamBegins) {
    // Nothing before a reconnect is continuous with what follows: not the still samples, not
    // the press.
    recent_.clear();
    if (pressed_) {
      pressed_ = false;
      end = PressEnd{s.tNs - pressedAt_, true};
    }
  }
  recent_.push_back(s);
  while (!recent_.empty() && s.tNs - recent_.front().tNs > 3 * settings.stillWindowNs + settings.longPressNs)
    recent_.pop_front();
  if (s.button && !pressed_) {
    pressed_ = true;
    pressedAt_ = s.tNs;
  } else if (!s.button && pressed_) {
    pressed_ = false;
    return PressEnd{s.tNs - pressedAt_, false};
  }
  return end;
}

std::vector<const StylusInput*> StylusPress::window(std::int64_t releaseNs, const Settings& settings) const {
  std::vector<const StylusInput*> out;
  for (const StylusInput& s : recent_)
    if (s.tNs >= pressedAt_ - settings.stillWindowNs && s.tNs <= releaseNs) out.push_back(&s);
  return out;
}

}  // namespace leafdig::acquisition
