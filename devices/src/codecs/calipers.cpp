// Caliper codecs (docs/devices.md). Each keeps the raw text of the reading and
// normalises to millimetres; malformed input is dropped and counted, never guessed.
#include "leafdig/devices/codecs/calipers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "codecs/codec_util.hpp"

namespace leafdig::devices::calipers {
namespace {

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
    s.remove_suffix(1);
  return std::string(s);
}

CaliperReading makeReading(double value, const std::string& unit, std::string raw) {
  CaliperReading r;
  r.rawValue = value;
  r.unit = unit;
  r.valueMm = detail::roundMm(unit == "in" ? value * kMmPerInch : value);
  r.raw = std::move(raw);
  return r;
}

// Splits complete lines ending in CR (optionally followed by LF) off `pending`.
template <class F>
void forEachLine(std::string& pending, std::span<const std::uint8_t> bytes, DecodeStats& stats, F&& onLine) {
  pending.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::size_t pos = 0;
  while (true) {
    const std::size_t cr = pending.find_first_of("\r\n", pos);
    if (cr == std::string::npos) break;
    std::size_t end = cr + 1;
    if (pending[cr] == '\r' && end < pending.size() && pending[end] == '\n') ++end;
    if (cr > pos) onLine(pending.substr(pos, cr - pos), pending.substr(pos, end - pos));
    pos = end;
  }
  pending.erase(0, pos);
  if (pending.size() > 128) {  // no terminator in sight: garbage
    ++stats.dropped;
    stats.discardedBytes += pending.size();
    pending.clear();
  }
}

int countDecimals(std::string_view s) {
  const auto dot = s.find_first_of(".,");
  if (dot == std::string_view::npos) return 0;
  int n = 0;
  for (std::size_t i = dot + 1; i < s.size() && detail::isDigit(s[i]); ++i) ++n;
  return n;
}

}  // namespace

std::optional<Number> parseNumber(std::string_view text) {
  std::string s = trim(text);
  Number n;
  std::string lower;
  for (char c : s) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* u : {"mm", "inch", "in", "\""}) {
    const std::string suf(u);
    if (lower.size() > suf.size() && lower.compare(lower.size() - suf.size(), suf.size(), suf) == 0) {
      n.unit = suf == "mm" ? "mm" : "in";
      s = trim(s.substr(0, s.size() - suf.size()));
      break;
    }
  }
  if (s.empty()) return std::nullopt;
  std::size_t i = 0;
  bool negative = false;
  if (s[0] == '+' || s[0] == '-') {
    negative = s[0] == '-';
    i = 1;
  }
  std::string digits;
  bool point = false;
  for (; i < s.size(); ++i) {
    const char c = s[i];
    if (detail::isDigit(c)) {
      digits += c;
    } else if ((c == '.' || c == ',') && !point) {
      digits += '.';
      point = true;
    } else {
      return std::nullopt;
    }
  }
  if (digits.empty() || digits == ".") return std::nullopt;
  const auto v = detail::toDouble(digits);
  if (!v) return std::nullopt;
  n.value = negative ? -*v : *v;
  if (n.value == 0.0) n.value = 0.0;
  return n;
}

// ---- HID keyboard -------------------------------------------------------------------------
namespace {
// Usage → character; 0 for keys we do not use, '\n' for a terminator.
char usageChar(std::uint8_t u, bool shift) {
  if (u >= 0x1E && u <= 0x26) return shift ? 0 : static_cast<char>('1' + (u - 0x1E));
  if (u == 0x27) return shift ? 0 : '0';
  if (u >= 0x59 && u <= 0x61) return static_cast<char>('1' + (u - 0x59));
  if (u >= 0x04 && u <= 0x1D) return static_cast<char>('a' + (u - 0x04));
  switch (u) {
    case 0x62: return '0';
    case 0x63: return '.';
    case 0x56: return '-';
    case 0x57: return '+';
    case 0x2D: return shift ? 0 : '-';
    case 0x2E: return shift ? '+' : 0;
    case 0x36: return shift ? 0 : ',';
    case 0x37: return shift ? 0 : '.';
    case 0x34: return shift ? '"' : 0;
    case 0x2C: return ' ';
    case 0x28:
    case 0x58:
    case 0x2B: return '\n';
    case 0x2A: return '\b';
    default: return 0;
  }
}
}  // namespace

void decodeHidReport(HidKeyboardState& st, std::span<const std::uint8_t> report, std::vector<CaliperReading>& out) {
  if (st.reportId && !report.empty()) report = report.subspan(1);
  if (report.size() < 8) {
    ++st.stats.dropped;
    return;
  }
  std::set<std::uint8_t> now;
  for (std::size_t i = 2; i < 8; ++i) {
    if (report[i] == 0x01) return;  // ErrorRollOver: the report carries no key state
    if (report[i] != 0) now.insert(report[i]);
  }
  const std::uint8_t mods = report[0];
  const bool shift = (mods & 0x22) != 0;
  const bool ctrlOrAlt = (mods & 0xDD) != 0;  // Ctrl/Alt/GUI: shortcuts such as Ctrl+A
  for (std::size_t i = 2; i < 8; ++i) {
    const std::uint8_t u = report[i];
    if (u == 0 || st.previous.count(u)) continue;  // held, not a new press
    if (ctrlOrAlt) continue;
    const char c = usageChar(u, shift);
    if (c == '\n') {
      if (!st.text.empty()) {
        const auto n = parseNumber(st.text);
        if (n) {
          out.push_back(makeReading(n->value, n->unit.empty() ? st.defaultUnit : n->unit, st.text));
          ++st.stats.records;
        } else {
          ++st.stats.dropped;
        }
      }
      st.text.clear();
    } else if (c == '\b') {
      if (!st.text.empty()) st.text.pop_back();
    } else if (c == 0) {
      st.text += '?';  // a key a gauge does not type: the reading will not parse
    } else {
      st.text += c;
    }
    if (st.text.size() > 40) {
      ++st.stats.dropped;
      st.text.clear();
    }
  }
  st.previous = std::move(now);
}

std::vector<std::vector<std::uint8_t>> encodeHidText(const std::string& text, bool keypad, bool reportId) {
  std::vector<std::vector<std::uint8_t>> reports;
  const auto add = [&](std::uint8_t mods, std::uint8_t usage) {
    std::vector<std::uint8_t> r(8, 0);
    r[0] = mods;
    r[2] = usage;
    if (reportId) r.insert(r.begin(), 1);
    reports.push_back(r);
    std::vector<std::uint8_t> release(8, 0);
    if (reportId) release.insert(release.begin(), 1);
    reports.push_back(release);
  };
  for (char c : text) {
    if (c >= '1' && c <= '9')
      add(0, static_cast<std::uint8_t>((keypad ? 0x59 : 0x1E) + (c - '1')));
    else if (c == '0')
      add(0, keypad ? 0x62 : 0x27);
    else if (c == '.')
      add(0, keypad ? 0x63 : 0x37);
    else if (c == ',')
      add(0, 0x36);
    else if (c == '-')
      add(0, keypad ? 0x56 : 0x2D);
    else if (c == '+')
      keypad ? add(0, 0x57) : add(0x02, 0x2E);
    else if (c == '\n')
      add(0, keypad ? 0x58 : 0x28);
    else if (c == '\t')
      add(0, 0x2B);
    else if (c == ' ')
      add(0, 0x2C);
    else if (c >= 'a' && c <= 'z')
      add(0, static_cast<std::uint8_t>(0x04 + (c - 'a')));
  }
  return reports;
}

// ---- Mitutoyo standard ASCII ------------------------------------------------------------
void decodeMitutoyo(MitutoyoState& st, std::span<const std::uint8_t> bytes, std::vector<CaliperReading>& out) {
  forEachLine(st.pending, bytes, st.stats, [&](const std::string& line, const std::string& raw) {
    if (line.size() >= 2 && line[0] == '9') {  // "9<channel><code>": error / status
      st.errors.push_back(line);
      ++st.stats.replies;
      return;
    }
    if (line.size() >= 1 && line[0] == '1') {  // device information reply
      ++st.stats.replies;
      return;
    }
    // "0" type, channel, 'A', sign, 8 characters with a floating point
    const bool shape = line.size() == 12 && line[0] == '0' && std::isalnum(static_cast<unsigned char>(line[1])) &&
                       line[2] == 'A' && (line[3] == '+' || line[3] == '-');
    std::optional<Number> n;
    if (shape) {
      const std::string data = line.substr(4);
      const bool digitsOk =
          std::count(data.begin(), data.end(), '.') == 1 &&
          std::all_of(data.begin(), data.end(), [](char c) { return c == '.' || detail::isDigit(c); });
      if (digitsOk) n = parseNumber(line.substr(3));
    }
    if (!n) {
      ++st.stats.dropped;
      return;
    }
    std::string unit = st.unit;
    if (unit == "auto") unit = countDecimals(line) >= 5 ? "in" : "mm";
    out.push_back(makeReading(n->value, unit, raw));
    ++st.stats.records;
  });
}

std::string encodeMitutoyo(double value, int decimals, int channel) {
  char num[32];
  std::snprintf(num, sizeof num, "%0*.*f", 8, decimals, std::abs(value));
  std::string s = "0" + std::to_string(channel % 10) + "A" + (value < 0 ? "-" : "+") + num + "\r";
  return s;
}

// ---- U-WAVE ------------------------------------------------------------------------------
void decodeUWave(UWaveState& st, std::span<const std::uint8_t> bytes, std::vector<CaliperReading>& out) {
  forEachLine(st.pending, bytes, st.stats, [&](const std::string& line, const std::string& raw) {
    if (line.rfind("DT", 0) != 0) {
      ++st.stats.replies;  // IR/RI/TI/ST dialogue lines
      return;
    }
    // "DT1" group(2) channel(2) ±value unit
    bool ok = line.size() >= 10 && line[2] == '1' && detail::isDigit(line[3]) && detail::isDigit(line[4]) &&
              detail::isDigit(line[5]) && detail::isDigit(line[6]) && (line[7] == '+' || line[7] == '-');
    std::optional<Number> n;
    std::string unit;
    if (ok) {
      const char u = line.back();
      if (u == 'M')
        unit = "mm";
      else if (u == 'I')
        unit = "in";
      else if (u == '0')
        unit = st.defaultUnit;
      else
        ok = false;
      if (ok) n = parseNumber(line.substr(7, line.size() - 8));
    }
    if (!ok || !n) {
      ++st.stats.dropped;
      return;
    }
    out.push_back(makeReading(n->value, unit, raw));
    ++st.stats.records;
  });
}

std::string encodeUWave(double value, const std::string& unit, int group, int channel) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "DT1%02d%02d%c%011.2f%c\r", group, channel, value < 0 ? '-' : '+', std::abs(value),
                unit == "in" ? 'I' : 'M');
  return buf;
}

// ---- Digimatic ----------------------------------------------------------------------------
std::optional<CaliperReading> decodeDigimatic(std::span<const std::uint8_t> d) {
  if (d.size() != 13) return std::nullopt;
  for (int i = 0; i < 4; ++i)
    if (d[static_cast<std::size_t>(i)] != 0xF) return std::nullopt;
  if (d[4] != 0 && d[4] != 8) return std::nullopt;
  long digits = 0;
  for (std::size_t i = 5; i < 11; ++i) {
    if (d[i] > 9) return std::nullopt;
    digits = digits * 10 + d[i];
  }
  if (d[11] > 5 || d[12] > 1) return std::nullopt;
  double v = static_cast<double>(digits) / std::pow(10.0, d[11]);
  if (d[4] == 8) v = -v;
  std::string raw;
  for (std::uint8_t n : d) raw += "0123456789ABCDEF"[n & 0xF];
  return makeReading(v == 0.0 ? 0.0 : v, d[12] ? "in" : "mm", raw);
}

std::array<std::uint8_t, 13> encodeDigimatic(double value, int decimals, bool inch) {
  std::array<std::uint8_t, 13> d{0xF, 0xF, 0xF, 0xF};
  d[4] = value < 0 ? 8 : 0;
  long digits = std::lround(std::abs(value) * std::pow(10.0, decimals));
  for (std::size_t i = 10; i >= 5; --i) {
    d[i] = static_cast<std::uint8_t>(digits % 10);
    digits /= 10;
  }
  d[11] = static_cast<std::uint8_t>(decimals);
  d[12] = inch ? 1 : 0;
  return d;
}

std::vector<std::uint8_t> digimaticBits(const std::array<std::uint8_t, 13>& nibbles) {
  std::vector<std::uint8_t> bits;
  for (std::uint8_t n : nibbles)
    for (int b = 0; b < 4; ++b) bits.push_back((n >> b) & 1);
  return bits;
}

std::optional<std::array<std::uint8_t, 13>> digimaticNibbles(std::span<const std::uint8_t> bits) {
  if (bits.size() != 52) return std::nullopt;
  std::array<std::uint8_t, 13> n{};
  for (std::size_t i = 0; i < 52; ++i) {
    if (bits[i] > 1) return std::nullopt;
    n[i / 4] = static_cast<std::uint8_t>(n[i / 4] | (bits[i] << (i % 4)));
  }
  return n;
}

// ---- Sylvac ------------------------------------------------------------------------------
const char* sylvacErrorMeaning(char code) {
  switch (code) {
    case '0': return "sensor error";
    case '1': return "unknown command";
    case '2': return "parity error (the port must be 4800 7E2)";
    case '3': return "value out of range";
    default: return "unknown error";
  }
}

void decodeSylvac(SylvacState& st, std::span<const std::uint8_t> bytes, std::vector<CaliperReading>& out) {
  forEachLine(st.pending, bytes, st.stats, [&](const std::string& rawLine, const std::string& raw) {
    const std::string line = trim(rawLine);
    std::string upper;
    for (char c : line) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (upper.empty()) return;
    if (upper == "MM" || upper == "IN") {  // echo of a unit command or reply to UNI?
      st.unit = upper == "MM" ? "mm" : "in";
      ++st.stats.replies;
      return;
    }
    if (upper.rfind("ERR", 0) == 0) {
      st.errors.push_back(upper);
      ++st.stats.replies;
      return;
    }
    if (upper.rfind("SY", 0) == 0) {
      st.identification = line;
      ++st.stats.replies;
      return;
    }
    static const char* const kEchoes[] = {"?",    "PRI",  "UNI?", "SET?", "ID?",  "OUT0", "OUT1", "KEY0",
                                          "KEY1", "RES2", "RES3", "PRE",  "PRE?", "TOL?", "BAT?", "OFF"};
    for (const char* e : kEchoes)
      if (upper == e) {
        ++st.stats.replies;
        return;
      }
    std::string body = rawLine;
    while (!body.empty() && (body.back() == ' ')) body.pop_back();
    std::string flag;
    if (!body.empty() && (body.back() == '<' || body.back() == '=' || body.back() == '>')) {
      flag = body.back();
      body.pop_back();
    }
    const bool signOk = !body.empty() && (body[0] == '+' || body[0] == '-' || body[0] == ' ');
    const auto n = signOk ? parseNumber(body) : std::nullopt;
    if (!n || body.find_first_of(".,") == std::string::npos) {
      ++st.stats.dropped;
      return;
    }
    auto r = makeReading(n->value, n->unit.empty() ? st.unit : n->unit, raw);
    r.flag = flag;
    out.push_back(std::move(r));
    ++st.stats.records;
  });
}

std::string encodeSylvac(double value, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+0*.*f\r", decimals + 5, decimals, value);
  return buf;
}

}  // namespace leafdig::devices::calipers
