// The studio's message layer as its handlers use it: parse (size and depth limits first), every
// checked getter on every field name the handlers read, and the error reply built from each
// refusal. A reply that is not valid JSON (e.g. invalid UTF-8 quoted from the input), any other
// exception, a crash or a deep recursion is a finding.
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "inhap/studio/protocol.hpp"

namespace {

void check_reply(const std::string& reply) {
  // nlohmann refuses invalid UTF-8 when parsing: the reply must come back as an error object.
  const auto j = nlohmann::json::parse(reply, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("type", "") != "error") std::abort();
}

template <class Fn>
void refused_or_ok(const inhap::studio::Message& m, Fn&& fn) {
  try {
    fn();
  } catch (const inhap::Error& e) {
    check_reply(inhap::studio::error_reply(m.type, e.what()));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inhap::studio;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)nlohmann::json(quote_input(text, 200)).dump();  // throws on invalid UTF-8: a finding
  Message m;
  try {
    m = parse_message(text);
  } catch (const inhap::Error& e) {
    check_reply(error_reply("?", e.what()));
    return 0;
  }
  static const char* keys[] = {
      "mode",  "x",           "y",      "z",     "nx",     "ny",    "nz",
      "press", "seq",         "ids",    "alpha", "taubin", "sqrt3", "points",
      "mesh",  "path",        "source", "model", "sys",    "shape", "probe_radius",
      "name",  "participant", "value",  "quick", "speed"};
  for (const char* k : keys) {
    refused_or_ok(m, [&] { (void)get_number(m, k, -1e4, 1e4); });
    refused_or_ok(m, [&] { (void)get_number_or(m, k, 0, 1, 0.5); });
    refused_or_ok(m, [&] { (void)get_integer(m, k, 0, 999); });
    refused_or_ok(m, [&] { (void)get_bool_or(m, k, false); });
    refused_or_ok(m, [&] { (void)get_string(m, k); });
    refused_or_ok(m, [&] { (void)get_choice(m, k, {"sampling", "explore", "tca", "cba"}); });
    refused_or_ok(m, [&] { (void)get_integer_list(m, k, 0, 1L << 40, 100000); });
  }
  (void)dump_safe(m.body);  // depth-limited: no deep recursion
  return 0;
}
