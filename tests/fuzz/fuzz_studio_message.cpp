// The studio's message layer as its handlers use it: parse (size and depth limits first), every
// checked getter on every field name the handlers read, and the error reply built from each
// refusal. Then the handlers' work that needs no server and no device: every string field of the
// message as a workspace path (input, output folder, read) in a workspace with links planted to a
// file outside it, and the bytes as a session file (open_session). A reply that is not valid
// JSON (e.g. invalid UTF-8 quoted from the input), any other exception, a read that returns the
// outside file's content, a crash or a deep recursion is a finding.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "inhap/studio/protocol.hpp"
#include "inhap/studio/security.hpp"
#include "inhap/studio/session_file.hpp"

namespace {

namespace fs = std::filesystem;
using inhap::studio::Workspace;

void check_reply(const std::string& reply) {
  // nlohmann refuses invalid UTF-8 when parsing: the reply must come back as an error object.
  const auto j = nlohmann::json::parse(reply, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("type", "") != "error") std::abort();
}

template <class Fn>
void refused_or_ok(const std::string& type, Fn&& fn) {
  try {
    fn();
  } catch (const inhap::Error& e) {
    check_reply(inhap::studio::error_reply(type, e.what()));
  }
}

constexpr const char* kSecret = "INHAP-FUZZ-OUTSIDE-THE-WORKSPACE";

// A workspace with a session file, a mesh in a subfolder and links that lead out of it (to a
// file and a folder outside, absolute and relative, and up from the subfolder), built once per
// process and removed at exit.
struct Fixture {
  fs::path base;
  std::unique_ptr<Workspace> ws;
  Fixture() {
    const char* tmp = std::getenv("TMPDIR");
    base =
        fs::path(tmp && *tmp ? tmp : "/tmp") / ("inhap-fuzz-studio-" + std::to_string(::getpid()));
    fs::remove_all(base);
    fs::create_directories(base / "outside");
    fs::create_directories(base / "ws/sub");
    std::ofstream(base / "outside/secret.ply") << kSecret;
    std::ofstream(base / "ws/sub/inside.ply") << "ply inside";
    std::ofstream(base / "ws/session.json")
        << R"({"format":"inhap-studio-session","version":1,"samples":[{"id":0,"point":[1,2,3],)"
           R"("threshold":[1,2,3],"direction":[0,0,1]}]})";
    fs::create_symlink("../outside/secret.ply", base / "ws/link.ply");
    fs::create_symlink(base / "outside/secret.ply", base / "ws/abs.json");
    fs::create_symlink("../outside", base / "ws/out");
    fs::create_symlink("..", base / "ws/sub/up");
    ws = std::make_unique<Workspace>(base / "ws");
  }
  ~Fixture() {
    ws.reset();
    std::error_code ec;
    fs::remove_all(base, ec);
  }
};

void workspace_paths(const std::string& type, const nlohmann::json& body) {
  static Fixture fx;
  for (const auto& [key, value] : body.items()) {
    if (!value.is_string()) continue;
    const std::string name = value.get<std::string>();
    refused_or_ok(type, [&] { (void)fx.ws->resolve(name); });
    refused_or_ok(type, [&] { (void)fx.ws->input(name); });
    refused_or_ok(type, [&] { (void)fx.ws->output(name); });
    refused_or_ok(type, [&] {
      if (fx.ws->read(name, 1 << 16).find(kSecret) != std::string::npos) std::abort();
    });
  }
}

void session_file(std::string_view text) {
  try {
    for (const auto& s : inhap::studio::parse_session_file(text, text.substr(0, 300))) {
      if (!s.point.allFinite() || !s.direction.allFinite() || s.id < 0) std::abort();
      (void)inhap::studio::sample_json(s).dump();
    }
  } catch (const inhap::Error& e) {
    check_reply(inhap::studio::error_reply("open_session", e.what()));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inhap::studio;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)nlohmann::json(quote_input(text, 200)).dump();  // throws on invalid UTF-8: a finding
  session_file(text);
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
  bool absent_tried = false;
  for (const char* k : keys) {
    // An absent field takes the same path in every getter: tried once per input (the throws
    // are most of the time per input).
    if (!m.body.contains(k)) {
      if (absent_tried) continue;
      absent_tried = true;
    }
    refused_or_ok(m.type, [&] { (void)get_number(m, k, -1e4, 1e4); });
    refused_or_ok(m.type, [&] { (void)get_number_or(m, k, 0, 1, 0.5); });
    refused_or_ok(m.type, [&] { (void)get_integer(m, k, 0, 999); });
    refused_or_ok(m.type, [&] { (void)get_bool_or(m, k, false); });
    refused_or_ok(m.type, [&] { (void)get_string(m, k); });
    refused_or_ok(m.type, [&] { (void)get_choice(m, k, {"sampling", "explore", "tca", "cba"}); });
    refused_or_ok(m.type, [&] { (void)get_integer_list(m, k, 0, 1L << 40, 100000); });
  }
  workspace_paths(m.type, m.body);
  (void)dump_safe(m.body);  // depth-limited: no deep recursion
  return 0;
}
