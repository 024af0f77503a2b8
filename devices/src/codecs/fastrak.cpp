// Polhemus FASTRAK records. Layout (manual p.57-65; docs/devices.md):
// '0', station '1'..'4', status (space = fine, a letter = BIT code), then the items of the
// output list. ASCII x,y,z and angles are right-aligned "%7.2f" columns that may touch
// ("30.01-150.70"), so fields are cut by column, never by whitespace.
#include "leafdig/devices/codecs/fastrak.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "codecs/codec_util.hpp"

namespace leafdig::devices::fastrak {
namespace {

using detail::fixedField;

std::size_t itemLength(int item, bool binary) {
  switch (item) {
    case 0: return 1;
    case 1: return 2;
    case 2:
    case 4: return binary ? 12 : 21;
    case 11: return binary ? 16 : 28;
    case 16: return 2;
    case 52:
    case 54: return binary ? 12 : 39;
    default:
      throw std::invalid_argument("FASTRAK output item " + std::to_string(item) +
                                  " is not supported (use 0, 1, 2, 4, 11, 16, 52, 54)");
  }
}

double unitScale(const Format& f) {
  return f.centimetres ? 10.0 : kMmPerInch;
}

std::optional<double> extendedField(std::string_view f) {  // "Sx.xxxxxESxx "
  if (f.size() != 13 || f[12] != ' ' || f[2] != '.' || f[8] != 'E') return std::nullopt;
  if (f[0] != ' ' && f[0] != '-') return std::nullopt;
  return detail::toDouble(f.substr(0, 12));
}

bool validStatus(char c) {
  return c == ' ' || detail::isLetter(c);
}

// Parses a complete record of the right length; false if anything is off.
bool parseRecord(const Format& fmt, std::string_view r, StylusSample& s) {
  if (r[0] != '0' || r[1] < '1' || r[1] > static_cast<char>('0' + fmt.stations) || !validStatus(r[2])) return false;
  s.station = r[1] - '0';
  if (r[2] != ' ') s.status.assign(1, r[2]);
  s.rawUnit.assign(fmt.centimetres ? "cm" : "in", 2);
  const double scale = unitScale(fmt);
  std::size_t off = 3;
  bool havePosition = false;
  for (int item : fmt.items) {
    const std::size_t len = itemLength(item, fmt.binary);
    const std::string_view f = r.substr(off, len);
    off += len;
    double v[4] = {0, 0, 0, 0};
    switch (item) {
      case 0:
        if (f[0] != ' ') return false;
        break;
      case 1:
        if (f != "\r\n") return false;
        break;
      case 16:
        if (f[0] != ' ' || (f[1] != '0' && f[1] != '1')) return false;
        s.button = f[1] == '1';
        break;
      case 2:
      case 4:
      case 52:
      case 54:
      case 11: {
        const int n = item == 11 ? 4 : 3;
        for (int k = 0; k < n; ++k) {
          std::optional<double> x;
          if (fmt.binary) {
            const float fv = detail::readF32(f.data() + 4 * k);
            if (std::isfinite(fv)) x = fv;
          } else if (item == 52 || item == 54) {
            x = extendedField(f.substr(static_cast<std::size_t>(13 * k), 13));
          } else {
            x = fixedField(f.substr(static_cast<std::size_t>(7 * k), 7), item == 11 ? 4 : 2);
          }
          if (!x) return false;
          v[k] = *x;
        }
        if (item == 2 || item == 52) {
          for (int k = 0; k < 3; ++k) {
            if (std::abs(v[k]) > 2000.0) return false;  // far outside any FASTRAK range
            s.positionMm[static_cast<std::size_t>(k)] = detail::roundMm(v[k] * scale);
          }
          havePosition = true;
        } else if (item == 4 || item == 54) {
          if (!detail::plausibleAngles(v[0], v[1], v[2])) return false;
          s.orientationDeg = Vec3{v[0], v[1], v[2]};
        } else {
          const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
          if (std::abs(norm - 1.0) > (fmt.binary ? 1e-3 : 2e-3)) return false;
          s.quaternion = std::array<double, 4>{v[0], v[1], v[2], v[3]};
        }
        break;
      }
      default: return false;
    }
  }
  return havePosition;
}

}  // namespace

std::size_t recordLength(const Format& format) {
  std::size_t n = 3;
  for (int item : format.items) n += itemLength(item, format.binary);
  return n;
}

std::string outputListCommand(const Format& format, int station) {
  std::string cmd = "O" + std::to_string(station);
  for (int item : format.items) cmd += "," + std::to_string(item);
  return cmd + "\r";
}

void decode(DecoderState& st, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out) {
  st.pending.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const std::string& p = st.pending;
  const std::size_t len = recordLength(st.format);
  std::size_t pos = 0;
  while (pos < p.size()) {
    const std::size_t avail = p.size() - pos;
    const bool boundary = st.synced || (pos > 0 ? p[pos - 1] : st.lastConsumed) == '\n';
    const char c = p[pos];
    if (boundary && c == '2') {  // a command reply ("21S…", "2 E*ERROR*…"): skip the line
      const std::size_t nl = p.find('\n', pos);
      if (nl == std::string::npos) {
        if (avail <= 300) break;  // wait for the rest of the line
        st.stats.discardedBytes += 1;
        ++pos;
        st.synced = false;
        continue;
      }
      ++st.stats.replies;
      pos = nl + 1;
      st.synced = true;
      continue;
    }
    if (c == '0') {
      if (avail < 3) break;
      const bool header =
          p[pos + 1] >= '1' && p[pos + 1] <= static_cast<char>('0' + st.format.stations) && validStatus(p[pos + 2]);
      if (header) {
        if (avail < len) break;  // wait for the whole record
        StylusSample s;
        if (parseRecord(st.format, std::string_view(p).substr(pos, len), s)) {
          detail::deliver(std::move(s), p.substr(pos, len), st.stats, out);
          pos += len;
          st.synced = true;
          continue;
        }
        if (boundary) {
          ++st.stats.dropped;  // a record began here and was corrupt
          st.synced = false;
          ++pos;
          continue;
        }
      }
    }
    ++st.stats.discardedBytes;
    st.synced = false;
    ++pos;
  }
  if (pos > 0) st.lastConsumed = p[pos - 1];
  st.pending.erase(0, pos);
}

std::string encode(const Format& fmt, const StylusSample& s) {
  std::string r;
  r += '0';
  r += static_cast<char>('0' + s.station);
  r += s.status == "ok" || s.status.empty() ? ' ' : s.status[0];
  const double scale = unitScale(fmt);
  const Vec3 o = s.orientationDeg.value_or(Vec3{0, 0, 0});
  const std::array<double, 4> q = s.quaternion.value_or(std::array<double, 4>{1, 0, 0, 0});
  for (int item : fmt.items) {
    switch (item) {
      case 0: r += ' '; break;
      case 1: r += "\r\n"; break;
      case 16:
        r += ' ';
        r += s.button ? '1' : '0';
        break;
      case 2:
      case 52:
      case 4:
      case 54:
      case 11: {
        const int n = item == 11 ? 4 : 3;
        for (int k = 0; k < n; ++k) {
          const auto ku = static_cast<std::size_t>(k);
          const double v = item == 2 || item == 52 ? s.positionMm[ku] / scale : item == 11 ? q[ku] : o[ku];
          if (fmt.binary) {
            detail::appendF32(r, v);
          } else if (item == 52 || item == 54) {
            r += detail::fmt("%12.5E ", v);
          } else {
            r += detail::fmt(item == 11 ? "%7.4f" : "%7.2f", v);
          }
        }
        break;
      }
      default: throw std::invalid_argument("FASTRAK output item " + std::to_string(item));
    }
  }
  return r;
}

std::string encodeStatus(const Status& st) {
  const int flags =
      (st.binary ? 1 : 0) | (st.centimetres ? 2 : 0) | (st.compensation ? 4 : 0) | (st.continuous ? 8 : 0);
  char buf[64];
  std::snprintf(buf, sizeof buf, "2%dS%03X000 3.0 leafdig FASTRAK emulator", st.station, flags);
  std::string line(buf);
  line.resize(53, ' ');
  return line + "\r\n";
}

bool parseStatus(std::string_view line, Status& st) {
  if (line.size() < 9 || line[0] != '2' || line[1] < '1' || line[1] > '4' || line[2] != 'S') return false;
  int flags = 0;
  for (int i = 3; i < 6; ++i) {
    const char c = line[static_cast<std::size_t>(i)];
    int d = 0;
    if (c >= '0' && c <= '9')
      d = c - '0';
    else if (c >= 'A' && c <= 'F')
      d = c - 'A' + 10;
    else if (c >= 'a' && c <= 'f')
      d = c - 'a' + 10;
    else
      return false;
    flags = flags * 16 + d;
  }
  st.station = line[1] - '0';
  st.binary = (flags & 1) != 0;
  st.centimetres = (flags & 2) != 0;
  st.compensation = (flags & 4) != 0;
  st.continuous = (flags & 8) != 0;
  return true;
}

}  // namespace leafdig::devices::fastrak
