// inhap studio: the session file (session_file.hpp).
#include "inhap/studio/session_file.hpp"

#include <fmt/format.h>

#include <set>

#include "inhap/studio/protocol.hpp"

namespace inhap::studio {
namespace {

nlohmann::json session_vec(const Vec3& p) {
  return nlohmann::json::array({p.x(), p.y(), p.z()});
}

Vec3 vec_from(const nlohmann::json& e, const char* what, const std::string& name) {
  const auto it = e.find(what);
  if (it == e.end() || !it->is_array() || it->size() != 3 || !(*it)[0].is_number() ||
      !(*it)[1].is_number() || !(*it)[2].is_number())
    throw ProtocolError(fmt::format("{}: \"{}\" expected [x, y, z]", name, what));
  const Vec3 v((*it)[0].get<double>(), (*it)[1].get<double>(), (*it)[2].get<double>());
  if (!v.allFinite()) throw ProtocolError(fmt::format("{}: \"{}\" not finite", name, what));
  return v;
}

bool flag(const nlohmann::json& e, const char* what, const std::string& name) {
  const auto it = e.find(what);
  if (it == e.end()) return false;
  if (!it->is_boolean())
    throw ProtocolError(fmt::format("{}: \"{}\" expected true or false", name, what));
  return it->get<bool>();
}

}  // namespace

nlohmann::json sample_json(const Sample& s) {
  return {{"id", s.id},
          {"point", session_vec(s.point)},
          {"threshold", session_vec(s.threshold)},
          {"direction", session_vec(s.direction)},
          {"t", s.t_contact},
          {"peak_force", s.peak_force},
          {"estimated", s.estimated}};
}

std::vector<Sample> parse_session_file(std::string_view text, std::string_view name_in) {
  const std::string name = quote_input(name_in, 200);
  // A sample is two levels down; anything deeper is not a session file (and would make the
  // recursive parts of nlohmann::json deep).
  if (json_depth(text, kMaxMessageDepth) > kMaxMessageDepth)
    throw ProtocolError(
        fmt::format("{}: expected an inhap studio session file (nested deeper "
                    "than {})",
                    name, kMaxMessageDepth));
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  const auto fmt_it = doc.is_object() ? doc.find("format") : doc.end();
  if (doc.is_discarded() || !doc.is_object() || fmt_it == doc.end() || !fmt_it->is_string() ||
      *fmt_it != "inhap-studio-session" || !doc.contains("samples") || !doc["samples"].is_array())
    throw ProtocolError(fmt::format("{}: expected an inhap studio session file", name));
  std::vector<Sample> loaded;
  std::set<long> ids;
  for (const auto& e : doc["samples"]) {
    const auto id = e.is_object() ? e.find("id") : e.end();
    if (id == e.end() || !id->is_number_integer())
      throw ProtocolError(fmt::format("{}: a sample without an integer \"id\"", name));
    // Within 0..2^52: the page keeps ids as doubles, and id + 1 cannot overflow.
    const bool fits = id->is_number_unsigned()
                          ? id->get<std::uint64_t>() <= (1ULL << 52)
                          : id->get<std::int64_t>() >= 0 && id->get<std::int64_t>() <= (1LL << 52);
    if (!fits) throw ProtocolError(fmt::format("{}: a sample \"id\" outside 0..2^52", name));
    Sample s;
    s.id = static_cast<long>(id->get<std::int64_t>());
    if (!ids.insert(s.id).second)
      throw ProtocolError(fmt::format("{}: sample id {} appears twice", name, s.id));
    s.point = vec_from(e, "point", name);
    s.threshold = vec_from(e, "threshold", name);
    s.direction = vec_from(e, "direction", name);
    s.deleted = flag(e, "deleted", name);
    s.estimated = flag(e, "estimated", name);
    loaded.push_back(s);
  }
  return loaded;
}

}  // namespace inhap::studio
