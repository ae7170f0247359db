#include "inhap/studio/protocol.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace inhap::studio {

const std::vector<std::string>& message_types() {
  static const std::vector<std::string> types = {
      "hello",    "mode",         "probe",        "delete",    "undo",      "reconstruct",
      "export",   "save_session", "open_session", "open_mesh", "algorithm", "experiment",
      "answer",   "next_trial",   "stats",        "summary",   "palpate",   "save_sys",
      "progress", "preview",      "apply_preview"};
  return types;
}

Message parse_message(std::string_view text) {
  if (text.size() > (1u << 20)) throw ProtocolError("message over 1 MB");
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw ProtocolError("expected a JSON object, got text that is not JSON");
  if (!j.is_object()) throw ProtocolError("expected a JSON object");
  const auto t = j.find("type");
  if (t == j.end() || !t->is_string()) throw ProtocolError("expected a string field \"type\"");
  Message m{t->get<std::string>(), std::move(j)};
  const auto& types = message_types();
  if (std::find(types.begin(), types.end(), m.type) == types.end())
    throw ProtocolError(fmt::format("unknown message type \"{}\"", m.type.substr(0, 64)));
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
  return nlohmann::json{{"type", "error"}, {"request", request}, {"message", message}}.dump();
}

}  // namespace inhap::studio
