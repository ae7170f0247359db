#include "inhap/studio/protocol.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace inhap::studio {

const std::vector<std::string>& message_types() {
  static const std::vector<std::string> types = {
      "hello",        "mode",         "probe",         "delete",       "undo",        "reconstruct",
      "export",       "save_session", "open_session",  "open_mesh",    "algorithm",   "experiment",
      "answer",       "next_trial",   "stats",         "summary",      "palpate",     "save_sys",
      "progress",     "preview",      "apply_preview", "model_record", "model_stop",  "model_train",
      "model_cancel", "model_source", "model_blind",   "model_answer", "model_stats", "servo"};
  return types;
}

std::string quote_input(std::string_view s, std::size_t max_bytes) {
  // Copies whole UTF-8 sequences (RFC 3629: no overlongs, no surrogates, at most U+10FFFF) and
  // replaces every other byte with U+FFFD; stops before max_bytes at a character boundary.
  std::string out;
  out.reserve(std::min(s.size(), max_bytes) + 4);
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  std::size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = byte(i);
    std::size_t n = c < 0x80                   ? 1
                    : (c >= 0xC2 && c <= 0xDF) ? 2
                    : (c >= 0xE0 && c <= 0xEF) ? 3
                    : (c >= 0xF0 && c <= 0xF4) ? 4
                                               : 0;
    bool ok = n > 0 && i + n <= s.size();
    for (std::size_t k = 1; ok && k < n; ++k) ok = (byte(i + k) & 0xC0) == 0x80;
    if (ok && n == 3) {
      const unsigned char d = byte(i + 1);
      ok = !(c == 0xE0 && d < 0xA0) && !(c == 0xED && d > 0x9F);
    }
    if (ok && n == 4) {
      const unsigned char d = byte(i + 1);
      ok = !(c == 0xF0 && d < 0x90) && !(c == 0xF4 && d > 0x8F);
    }
    const std::string_view piece = ok ? s.substr(i, n) : std::string_view("\xEF\xBF\xBD");
    if (out.size() + piece.size() > max_bytes) {
      out += "...";
      break;
    }
    out += piece;
    i += ok ? n : 1;
  }
  return out;
}

std::size_t json_depth(std::string_view text, std::size_t limit) {
  // Brackets outside strings (a backslash escapes the next byte inside one); stops counting at
  // limit + 1 so that the caller's check costs no more than the scan.
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) return deepest;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

std::string dump_safe(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

Message parse_message(std::string_view text) {
  if (text.size() > kMaxMessageBytes)
    throw ProtocolError(fmt::format("message over {} bytes", kMaxMessageBytes));
  if (json_depth(text, kMaxMessageDepth) > kMaxMessageDepth)
    throw ProtocolError(fmt::format("message nested deeper than {} levels", kMaxMessageDepth));
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw ProtocolError("expected a JSON object, got text that is not JSON");
  if (!j.is_object()) throw ProtocolError("expected a JSON object");
  const auto t = j.find("type");
  if (t == j.end() || !t->is_string()) throw ProtocolError("expected a string field \"type\"");
  Message m{t->get<std::string>(), std::move(j)};
  const auto& types = message_types();
  if (std::find(types.begin(), types.end(), m.type) == types.end())
    throw ProtocolError(fmt::format("unknown message type \"{}\"", quote_input(m.type, 64)));
  return m;
}

namespace {

const nlohmann::json& field(const Message& m, const char* key) {
  const auto it = m.body.find(key);
  if (it == m.body.end()) throw ProtocolError(fmt::format("{}: field \"{}\" missing", m.type, key));
  return *it;
}

}  // namespace

double get_number(const Message& m, const char* key, double lo, double hi) {
  const nlohmann::json& v = field(m, key);
  if (!v.is_number()) throw ProtocolError(fmt::format("{}: \"{}\" expected a number", m.type, key));
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < lo || d > hi)
    throw ProtocolError(
        fmt::format("{}: \"{}\" expected a number in [{:g}, {:g}]", m.type, key, lo, hi));
  return d;
}

double get_number_or(const Message& m, const char* key, double lo, double hi, double fallback) {
  return m.body.contains(key) ? get_number(m, key, lo, hi) : fallback;
}

long get_integer(const Message& m, const char* key, long lo, long hi) {
  const nlohmann::json& v = field(m, key);
  if (!v.is_number_integer())
    throw ProtocolError(fmt::format("{}: \"{}\" expected an integer", m.type, key));
  const long i = v.get<long>();
  if (i < lo || i > hi)
    throw ProtocolError(
        fmt::format("{}: \"{}\" expected an integer in [{}, {}]", m.type, key, lo, hi));
  return i;
}

bool get_bool_or(const Message& m, const char* key, bool fallback) {
  if (!m.body.contains(key)) return fallback;
  const nlohmann::json& v = field(m, key);
  if (!v.is_boolean())
    throw ProtocolError(fmt::format("{}: \"{}\" expected true or false", m.type, key));
  return v.get<bool>();
}

std::string get_string(const Message& m, const char* key, std::size_t max_size) {
  const nlohmann::json& v = field(m, key);
  if (!v.is_string()) throw ProtocolError(fmt::format("{}: \"{}\" expected a string", m.type, key));
  std::string s = v.get<std::string>();
  if (s.empty() || s.size() > max_size)
    throw ProtocolError(fmt::format("{}: \"{}\" expected 1-{} characters", m.type, key, max_size));
  return s;
}

std::string get_choice(const Message& m, const char* key, const std::vector<std::string>& choices) {
  std::string s = get_string(m, key, 64);
  if (std::find(choices.begin(), choices.end(), s) == choices.end())
    throw ProtocolError(
        fmt::format("{}: \"{}\" expected one of {}", m.type, key, fmt::join(choices, ", ")));
  return s;
}

std::vector<long> get_integer_list(const Message& m, const char* key, long lo, long hi,
                                   std::size_t max_items) {
  const nlohmann::json& v = field(m, key);
  if (!v.is_array() || v.empty() || v.size() > max_items)
    throw ProtocolError(
        fmt::format("{}: \"{}\" expected a list of 1-{} integers", m.type, key, max_items));
  std::vector<long> out;
  for (const auto& e : v) {
    if (!e.is_number_integer() || e.get<long>() < lo || e.get<long>() > hi)
      throw ProtocolError(
          fmt::format("{}: \"{}\" expected integers in [{}, {}]", m.type, key, lo, hi));
    out.push_back(e.get<long>());
  }
  return out;
}

std::string error_reply(std::string_view request, std::string_view message) {
  try {
    return dump_safe(nlohmann::json{{"type", "error"},
                                    {"request", quote_input(request, 64)},
                                    {"message", quote_input(message, 1024)}});
  } catch (...) {  // out of memory: a reply that needs none
    return R"({"type":"error","request":"?","message":"internal error"})";
  }
}

}  // namespace inhap::studio
