// The generic line digitizer (docs/devices.md): framing by terminator, fixed
// length or sync bytes; fields by columns, tokens or a regular expression.
#include "leafdig/devices/codecs/line_digitizer.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "codecs/codec_util.hpp"

namespace leafdig::devices::line {
namespace {

using nlohmann::json;

Field readField(const json& f, FieldMode mode, const std::string& name) {
  if (f.is_null()) return {};
  if (mode == FieldMode::Columns) {
    if (!f.is_array() || f.size() != 2 || !f[0].is_number_integer() || !f[1].is_number_integer() ||
        f[0].get<int>() < 0 || f[1].get<int>() <= 0)
      throw std::invalid_argument("fields." + name + ": columns need [start, width] with start >= 0 and width > 0");
    return {f[0].get<int>(), f[1].get<int>()};
  }
  if (!f.is_number_integer() || f.get<int>() < 0)
    throw std::invalid_argument("fields." + name + ": give a token index or regex group (>= 0)");
  return {f.get<int>(), 0};
}

std::string unescape(const std::string& s) {  // JSON already decodes \r \n; allow "\\r" too
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size()) {
      const char n = s[++i];
      out += n == 'r' ? '\r' : n == 'n' ? '\n' : n == 't' ? '\t' : n;
    } else {
      out += s[i];
    }
  }
  return out;
}

std::string fieldText(const DecoderState& st, const std::string& rec, const std::vector<std::string>& tokens,
                      const std::smatch* m, Field f) {
  switch (st.config.mode) {
    case FieldMode::Columns:
      if (static_cast<std::size_t>(f.a + f.b) > rec.size()) return {};
      return rec.substr(static_cast<std::size_t>(f.a), static_cast<std::size_t>(f.b));
    case FieldMode::Tokens:
      return static_cast<std::size_t>(f.a) < tokens.size() ? tokens[static_cast<std::size_t>(f.a)] : std::string();
    case FieldMode::Regex:
      return m && static_cast<std::size_t>(f.a) < m->size() ? (*m)[static_cast<std::size_t>(f.a)].str() : std::string();
  }
  return {};
}

}  // namespace

Config parseConfig(const std::string& text) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw std::invalid_argument(std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw std::invalid_argument("the configuration must be a JSON object");
  Config c;
  try {
    for (const auto& l : j.value("init", json::array())) c.init.push_back(unescape(l.get<std::string>()));
    c.poll = unescape(j.value("poll", std::string()));
    c.start = unescape(j.value("start", std::string()));
    c.stop = unescape(j.value("stop", std::string()));
    c.baud = j.value("baud", 9600);
    const json fr = j.value("framing", json::object());
    c.terminator = unescape(fr.value("terminator", std::string("\r\n")));
    c.length = fr.value("length", std::size_t{0});
    c.sync = unescape(fr.value("sync", std::string()));
    c.maxLength = fr.value("max_length", std::size_t{256});
    if (c.length == 0 && c.terminator.empty())
      throw std::invalid_argument("framing: give a terminator or a fixed length");
    const json f = j.value("fields", json::object());
    const std::string mode = f.value("mode", std::string("tokens"));
    if (mode == "columns")
      c.mode = FieldMode::Columns;
    else if (mode == "tokens")
      c.mode = FieldMode::Tokens;
    else if (mode == "regex")
      c.mode = FieldMode::Regex;
    else
      throw std::invalid_argument("fields.mode must be columns, tokens or regex, not '" + mode + "'");
    if (c.mode == FieldMode::Regex) {
      c.regex = f.value("regex", std::string());
      if (c.regex.empty()) throw std::invalid_argument("fields.regex is required in regex mode");
      try {
        (void)std::regex(c.regex);
      } catch (const std::regex_error& e) {
        throw std::invalid_argument("fields.regex does not compile: " + std::string(e.what()));
      }
    }
    if (f.contains("separators")) c.tokenSeparators = f["separators"].get<std::string>();
    const auto field = [&](const char* name, Field def) {
      return f.contains(name) ? readField(f[name], c.mode, name) : def;
    };
    const bool columns = c.mode == FieldMode::Columns;
    c.x = field("x", columns ? Field{} : Field{0});
    c.y = field("y", columns ? Field{} : Field{1});
    c.z = field("z", columns ? Field{} : Field{2});
    if (!c.x.present() || !c.y.present() || !c.z.present())
      throw std::invalid_argument("fields: x, y and z are required");
    c.az = field("az", {});
    c.el = field("el", {});
    c.roll = field("roll", {});
    c.button = field("button", {});
    c.station = field("station", {});
    c.status = field("status", {});
    c.okStatus = f.value("ok_status", std::string());
    c.unit = j.value("unit", std::string("mm"));
    if (c.unit == "mm")
      c.scaleToMm = 1;
    else if (c.unit == "cm")
      c.scaleToMm = 10;
    else if (c.unit == "m")
      c.scaleToMm = 1000;
    else if (c.unit == "in")
      c.scaleToMm = kMmPerInch;
    else
      throw std::invalid_argument("unit must be mm, cm, m or in, not '" + c.unit + "'");
    if (j.contains("axes")) {
      const auto& a = j["axes"];
      if (!a.is_array() || a.size() != 3) throw std::invalid_argument("axes: give three, e.g. [\"x\",\"-z\",\"y\"]");
      bool used[3] = {false, false, false};
      for (std::size_t i = 0; i < 3; ++i) {
        std::string s = a[i].get<std::string>();
        double sign = 1;
        if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
          sign = s[0] == '-' ? -1 : 1;
          s = s.substr(1);
        }
        if (s != "x" && s != "y" && s != "z") throw std::invalid_argument("axes: '" + s + "' is not x, y or z");
        const int k = s[0] - 'x';
        if (used[k]) throw std::invalid_argument("axes: '" + s + "' appears twice");
        used[k] = true;
        c.axisMap[i] = k;
        c.axisSign[i] = sign;
      }
    }
  } catch (const json::exception& e) {
    throw std::invalid_argument(std::string("wrong type in the configuration: ") + e.what());
  }
  return c;
}

bool parseRecord(DecoderState& st, const std::string& rec, StylusSample& s) {
  const Config& c = st.config;
  std::vector<std::string> tokens;
  std::smatch m;
  const std::smatch* mp = nullptr;
  if (c.mode == FieldMode::Tokens) {
    std::size_t i = 0;
    while (i < rec.size()) {
      while (i < rec.size() && c.tokenSeparators.find(rec[i]) != std::string::npos) ++i;
      std::size_t j = i;
      while (j < rec.size() && c.tokenSeparators.find(rec[j]) == std::string::npos) ++j;
      if (j > i) tokens.push_back(rec.substr(i, j - i));
      i = j;
    }
  } else if (c.mode == FieldMode::Regex) {
    if (!st.compiled) st.compiled.emplace(c.regex);
    if (!std::regex_search(rec, m, *st.compiled)) return false;
    mp = &m;
  }
  Vec3 in{};
  const Field xyz[3] = {c.x, c.y, c.z};
  for (std::size_t k = 0; k < 3; ++k) {
    const auto v = detail::toDouble(fieldText(st, rec, tokens, mp, xyz[k]));
    if (!v) return false;
    in[k] = detail::roundMm(*v * c.scaleToMm);
  }
  for (std::size_t k = 0; k < 3; ++k) s.positionMm[k] = c.axisSign[k] * in[static_cast<std::size_t>(c.axisMap[k])];
  if (c.az.present() && c.el.present() && c.roll.present()) {
    const auto a = detail::toDouble(fieldText(st, rec, tokens, mp, c.az));
    const auto e = detail::toDouble(fieldText(st, rec, tokens, mp, c.el));
    const auto r = detail::toDouble(fieldText(st, rec, tokens, mp, c.roll));
    if (!a || !e || !r) return false;
    s.orientationDeg = Vec3{*a, *e, *r};
  }
  if (c.button.present()) {
    const auto b = detail::toDouble(fieldText(st, rec, tokens, mp, c.button));
    if (!b) return false;
    s.button = *b != 0;
  }
  if (c.station.present()) {
    const auto n = detail::toDouble(fieldText(st, rec, tokens, mp, c.station));
    if (!n || *n < 0 || *n > 255) return false;
    s.station = static_cast<int>(*n);
  }
  if (c.status.present()) {
    std::string t = fieldText(st, rec, tokens, mp, c.status);
    while (!t.empty() && t.back() == ' ') t.pop_back();
    while (!t.empty() && t.front() == ' ') t.erase(0, 1);
    s.status = (t.empty() || t == c.okStatus) ? "ok" : t;
  }
  s.rawUnit = c.unit;
  return true;
}

void decode(DecoderState& st, std::span<const std::uint8_t> bytes, std::vector<StylusSample>& out) {
  const Config& c = st.config;
  st.pending.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::string& p = st.pending;
  std::size_t pos = 0;
  const auto emit = [&](const std::string& body, std::string raw) {
    StylusSample s;
    if (parseRecord(st, body, s)) {
      detail::deliver(std::move(s), std::move(raw), st.stats, out);
    } else {
      ++st.stats.dropped;
    }
  };
  while (pos < p.size()) {
    if (!c.sync.empty()) {  // every record starts with the sync bytes
      const std::size_t at = p.find(c.sync, pos);
      if (at == std::string::npos) {
        const std::size_t keep = std::min(p.size() - pos, c.sync.size() - 1);
        st.stats.discardedBytes += p.size() - pos - keep;
        pos = p.size() - keep;
        break;
      }
      st.stats.discardedBytes += at - pos;
      pos = at;
    }
    if (c.length > 0) {
      if (p.size() - pos < c.length) break;
      const std::string rec = p.substr(pos, c.length);
      emit(rec.substr(c.sync.size()), rec);
      pos += c.length;
      continue;
    }
    const std::size_t end = p.find(c.terminator, pos + c.sync.size());
    if (end == std::string::npos) {
      if (p.size() - pos > c.maxLength) {  // a runaway line: drop it and look for the next
        ++st.stats.dropped;
        const std::size_t n = p.size() - pos;
        st.stats.discardedBytes += n;
        pos = p.size();
      }
      break;
    }
    const std::size_t recEnd = end + c.terminator.size();
    if (end - pos > c.maxLength) {
      ++st.stats.dropped;
    } else if (end > pos) {
      emit(p.substr(pos + c.sync.size(), end - pos - c.sync.size()), p.substr(pos, recEnd - pos));
    }
    pos = recEnd;
  }
  p.erase(0, pos);
}

}  // namespace leafdig::devices::line
