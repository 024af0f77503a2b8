// Polhemus Patriot / Liberty records (docs/devices.md). Binary frames carry an
// 8-byte header ("PA"/"LY", station, command, error, reserved, u16 LE payload size); the
// ASCII layout is fixed 9-character columns after a 4-character header (docs/devices.md).
#include "leafdig/devices/codecs/polhemus.hpp"

#include <cmath>
#include <stdexcept>

#include "codecs/codec_util.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::devices::polhemus {
namespace {

std::size_t binaryItem(int item) {
  switch (item) {
    case 0: return 1;
    case 1: return 2;
    case 2:
    case 5: return 12;
    case 7: return 16;
    case 8:
    case 9:
    case 10:
    case 11: return 4;
    default:
      throw std::invalid_argument("Patriot/Liberty output item " + std::to_string(item) +
                                  " is not supported (use 0, 1, 2, 5, 7, 8, 9, 10, 11)");
  }
}

std::size_t asciiItem(int item) {
  switch (item) {
    case 0: return 1;
    case 1: return 2;
    case 2:
    case 5: return 27;
    case 7: return 36;
    case 8:
    case 9: return 10;
    case 10: return 2;
    case 11: return 4;
    default: return binaryItem(item);  // throws with the message above
  }
}

const char* tag(Model m) {
  return m == Model::Patriot ? "PA" : "LY";
}
double scale(const Format& f) {
  return f.centimetres ? 10.0 : kMmPerInch;
}

bool applyValues(const Format& fmt, int item, const double* v, StylusSample& s) {
  if (item == 2) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(v[k]) > 2000.0) return false;
      s.positionMm[static_cast<std::size_t>(k)] = detail::roundMm(v[k] * scale(fmt));
    }
  } else if (item == 5) {
    if (!detail::plausibleAngles(v[0], v[1], v[2])) return false;
    s.orientationDeg = Vec3{v[0], v[1], v[2]};
  } else if (item == 7) {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    if (std::abs(n - 1.0) > (fmt.binary ? 1e-3 : 2e-3)) return false;
    s.quaternion = std::array<double, 4>{v[0], v[1], v[2], v[3]};
  }
  return true;
}

bool hasPosition(const Format& f) {
  for (int i : f.items)
    if (i == 2) return true;
  return false;
}

bool parseBinary(const Format& fmt, std::string_view r, StylusSample& s) {
  const int station = static_cast<unsigned char>(r[2]);
  if (station < 1 || station > fmt.stations || (r[3] != 'C' && r[3] != 'P')) return false;
  const auto err = static_cast<unsigned char>(r[4]);
  if (err != 0 && err != ' ') {
    if (detail::isLetter(static_cast<char>(err)))
      s.status.assign(1, static_cast<char>(err));
    else
      s.status = "E" + std::to_string(err);
  }
  s.station = station;
  s.rawUnit.assign(fmt.centimetres ? "cm" : "in", 2);
  std::size_t off = 8;
  for (int item : fmt.items) {
    const char* d = r.data() + off;
    const std::size_t n = binaryItem(item);
    off += n;
    switch (item) {
      case 0:
        if (*d != ' ') return false;
        break;
      case 1:
        if (d[0] != '\r' || d[1] != '\n') return false;
        break;
      case 10: {
        const std::uint32_t b = detail::readU32(d);
        if (b > 0xff) return false;
        s.button = (b & 1u) != 0;
        break;
      }
      case 8:
      case 9:
      case 11: break;
      default: {
        double v[4];
        for (std::size_t k = 0; k < n / 4; ++k) {
          const float f = detail::readF32(d + 4 * k);
          if (!std::isfinite(f)) return false;
          v[k] = f;
        }
        if (!applyValues(fmt, item, v, s)) return false;
      }
    }
  }
  return hasPosition(fmt);
}

bool parseAscii(const Format& fmt, std::string_view r, StylusSample& s) {
  if (!(r[0] == ' ' || detail::isDigit(r[0])) || !detail::isDigit(r[1])) return false;
  const int station = (r[0] == ' ' ? 0 : (r[0] - '0') * 10) + (r[1] - '0');
  if (station < 1 || station > fmt.stations) return false;
  if (r[2] != ' ' && !detail::isLetter(r[2])) return false;
  if (r[3] != ' ') return false;
  if (r[2] != ' ') s.status.assign(1, r[2]);
  s.station = station;
  s.rawUnit.assign(fmt.centimetres ? "cm" : "in", 2);
  std::size_t off = 4;
  for (int item : fmt.items) {
    const std::string_view f = r.substr(off, asciiItem(item));
    off += f.size();
    switch (item) {
      case 0:
        if (f[0] != ' ') return false;
        break;
      case 1:
        if (f != "\r\n") return false;
        break;
      case 10:
        if (f[0] != ' ' || (f[1] != '0' && f[1] != '1')) return false;
        s.button = f[1] == '1';
        break;
      case 8:
      case 9:
      case 11: {
        for (char c : f)
          if (c != ' ' && !detail::isDigit(c) && c != '-') return false;
        if (!detail::toDouble(f)) return false;
        break;
      }
      default: {
        double v[4];
        const int decimals = item == 7 ? 4 : 3;
        for (std::size_t k = 0; k < f.size() / 9; ++k) {
          const auto x = detail::fixedField(f.substr(9 * k, 9), decimals);
          if (!x) return false;
          v[k] = *x;
        }
        if (!applyValues(fmt, item, v, s)) return false;
      }
    }
  }
  return hasPosition(fmt);
}

}  // namespace

namespace {
constexpr NameTable<Model, 2> kModels{{{Model::Patriot, "patriot"}, {Model::Liberty, "liberty"}}};
}  // namespace

const char* toString(Model m) {
  return nameIn(kModels, m);
}

std::size_t payloadLength(const Format& f) {
  std::size_t n = 0;
  for (int i : f.items) n += binaryItem(i);
  return n;
}

std::size_t asciiLength(const Format& f) {
  std::size_t n = 4;
  for (int i : f.items) n += asciiItem(i);
  return n;
}

std::string outputListCommand(const Format& f) {
  std::string cmd = "O*";
  for (int i : f.items) cmd += "," + std::to_string(i);
  return cmd + "\r";
}

void decode(DecoderState& st, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out) {
  st.pending.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const std::string& p = st.pending;
  const Format& fmt = st.format;
  std::size_t pos = 0;
  if (fmt.binary) {
    const std::size_t len = 8 + payloadLength(fmt);
    const char* t = tag(fmt.model);
    while (pos < p.size()) {
      const std::size_t avail = p.size() - pos;
      const bool tagHere =
          p[pos] == t[0] && (avail < 2 || p[pos + 1] == t[1] || (fmt.model == Model::Liberty && p[pos + 1] == 'U'));
      if (tagHere) {
        if (avail < len) break;
        const std::size_t size = detail::readU16(p.data() + pos + 6);
        StylusSample s;
        if (size == len - 8 && parseBinary(fmt, std::string_view(p).substr(pos, len), s)) {
          detail::deliver(std::move(s), p.substr(pos, len), st.stats, out);
          pos += len;
          st.synced = true;
          continue;
        }
        if (st.synced) {
          ++st.stats.dropped;
          st.synced = false;
          ++pos;
          continue;
        }
      }
      ++st.stats.discardedBytes;
      st.synced = false;
      ++pos;
    }
  } else {
    const std::size_t len = asciiLength(fmt);
    while (pos < p.size()) {
      const std::size_t avail = p.size() - pos;
      const bool boundary = st.synced || (pos > 0 ? p[pos - 1] : st.lastConsumed) == '\n';
      if (avail < 4) break;
      const bool header = (p[pos] == ' ' || detail::isDigit(p[pos])) && detail::isDigit(p[pos + 1]) &&
                          (p[pos + 2] == ' ' || detail::isLetter(p[pos + 2])) && p[pos + 3] == ' ';
      if (header) {
        if (avail < len) break;
        StylusSample s;
        if (parseAscii(fmt, std::string_view(p).substr(pos, len), s)) {
          detail::deliver(std::move(s), p.substr(pos, len), st.stats, out);
          pos += len;
          st.synced = true;
          continue;
        }
        if (boundary) {
          ++st.stats.dropped;
          st.synced = false;
          ++pos;
          continue;
        }
      } else if (boundary) {  // a text line (banner, WhoAmI reply) or garbage: skip the line
        const std::size_t nl = p.find('\n', pos);
        if (nl == std::string::npos && avail <= 300) break;
        const std::size_t end = nl == std::string::npos ? p.size() : nl + 1;
        bool printable = true;
        for (std::size_t i = pos; i < end; ++i) {
          const auto u = static_cast<unsigned char>(p[i]);
          if (u >= 0x7f || (u < 0x20 && u != '\r' && u != '\n')) printable = false;
        }
        if (printable)
          ++st.stats.replies;
        else
          st.stats.discardedBytes += end - pos;
        pos = end;
        st.synced = nl != std::string::npos;
        continue;
      }
      ++st.stats.discardedBytes;
      st.synced = false;
      ++pos;
    }
  }
  if (pos > 0) st.lastConsumed = p[pos - 1];
  st.pending.erase(0, pos);
}

std::string encode(const Format& fmt, const StylusSample& s, std::uint32_t frame, std::uint32_t timestampMs,
                   char command) {
  const double sc = scale(fmt);
  const Vec3 o = s.orientationDeg.value_or(Vec3{0, 0, 0});
  const std::array<double, 4> q = s.quaternion.value_or(std::array<double, 4>{1, 0, 0, 0});
  const char status = s.status == "ok" || s.status.empty() ? 0 : s.status[0];
  std::string r;
  if (fmt.binary) {
    r += tag(fmt.model);
    r += static_cast<char>(s.station);
    r += command;
    r += status;
    r += '\0';
    detail::appendU16(r, static_cast<std::uint16_t>(payloadLength(fmt)));
  } else {
    r += detail::fmt("%2.0f", s.station);
    r += status ? status : ' ';
    r += ' ';
  }
  for (int item : fmt.items) {
    switch (item) {
      case 0: r += ' '; break;
      case 1: r += "\r\n"; break;
      case 8:
      case 9:
        if (fmt.binary)
          detail::appendU32(r, item == 8 ? timestampMs : frame);
        else
          r += detail::fmt("%10.0f", item == 8 ? timestampMs : frame);
        break;
      case 10:
        if (fmt.binary)
          detail::appendU32(r, s.button ? 1u : 0u);
        else
          r += s.button ? " 1" : " 0";
        break;
      case 11:
        if (fmt.binary)
          detail::appendU32(r, 0);
        else
          r += "   0";
        break;
      default: {
        const int n = item == 7 ? 4 : 3;
        for (int k = 0; k < n; ++k) {
          const auto ku = static_cast<std::size_t>(k);
          const double v = item == 2 ? s.positionMm[ku] / sc : item == 5 ? o[ku] : q[ku];
          if (fmt.binary)
            detail::appendF32(r, v);
          else
            r += detail::fmt(item == 7 ? "%9.4f" : "%9.3f", v);
        }
      }
    }
  }
  return r;
}

}  // namespace leafdig::devices::polhemus
