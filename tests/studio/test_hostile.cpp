// inhap studio against a hostile local user: every message gets a reply (never an exception that
// escapes a handler), error texts quote input as valid UTF-8 and capped, JSON depth and size are
// limited before parsing, and workspace files cannot lead outside the workspace.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/studio/protocol.hpp"
#include "inhap/studio/session.hpp"
#include "support/temp_dir.hpp"

using namespace inhap::studio;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string repeat(std::string_view s, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

// The reply parses as JSON (nlohmann refuses invalid UTF-8) and is an error for `request`.
json expect_error(Session& s, const std::string& text) {
  std::string r;
  EXPECT_NO_THROW(r = s.handle(text));
  json j = json::parse(r, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << r.substr(0, 200);
  if (j.is_discarded()) return j;
  EXPECT_EQ(j.value("type", ""), "error") << r.substr(0, 200);
  EXPECT_LE(j.value("message", "").size(), 1100u);
  return j;
}

std::string session_file(int n) {
  json pts = json::array();
  for (int i = 0; i < n; ++i)
    pts.push_back({{"id", i},
                   {"point", {i * 3.0, 0.0, 10.0}},
                   {"threshold", {i * 3.0, 0.0, 10.2}},
                   {"direction", {0, 0, 1}}});
  return json{{"format", "inhap-studio-session"}, {"version", 1}, {"samples", pts}}.dump();
}

}  // namespace

TEST(StudioHostile, QuoteInputIsValidUtf8AndCapped) {
  const std::string e = "\xC3\xA9";  // é
  const std::string q = quote_input("a" + repeat(e, 40), 64);
  EXPECT_LE(q.size(), 67u);
  EXPECT_NO_THROW((void)json(q).dump());  // dump() throws on invalid UTF-8
  EXPECT_EQ(quote_input("ok"), "ok");
  EXPECT_EQ(quote_input("a\xFF"
                        "b"),
            "a\xEF\xBF\xBD"
            "b");
  EXPECT_EQ(quote_input("\xED\xA0\x80"), repeat("\xEF\xBF\xBD", 3));  // a surrogate
  EXPECT_EQ(quote_input("\xC3"), "\xEF\xBF\xBD");                     // cut sequence
}

TEST(StudioHostile, UnknownTypeCutInsideACharacterGetsAnErrorReply) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  // 92 bytes; before, the error text cut the type inside an "é" and json::dump threw.
  const json j = expect_error(s, json{{"type", "a" + repeat("\xC3\xA9", 40)}}.dump());
  EXPECT_NE(j.value("message", "").find("unknown message type"), std::string::npos);
}

TEST(StudioHostile, LongNonAsciiFileNameGetsAnErrorReply) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  const std::string name = "a" + repeat("\xC3\xA9", 150) + ".ply";
  expect_error(s, json{{"type", "export"}, {"points", name}}.dump());
  expect_error(s, json{{"type", "save_session"}, {"path", name}}.dump());
  expect_error(s, json{{"type", "open_session"}, {"path", name}}.dump());
  EXPECT_THROW((void)ws.resolve(name), inhap::Error);
  try {
    (void)ws.resolve(name);
  } catch (const inhap::Error& e) {
    EXPECT_NO_THROW((void)json(std::string(e.what())).dump());
  }
}

TEST(StudioHostile, DeeplyNestedMessagesAreRefusedBeforeParsing) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  // 200 KB nested 100,000 deep: before, the log line's recursive dump() overflowed the stack.
  const std::string deep =
      R"({"type":"stats","x":)" + repeat("[", 100000) + repeat("]", 100000) + "}";
  const json j = expect_error(s, deep);
  EXPECT_NE(j.value("message", "").find("nested deeper"), std::string::npos);
  EXPECT_EQ(json_depth(deep, kMaxMessageDepth), kMaxMessageDepth + 1);
  // Brackets inside strings do not count; a normal stats message is fine.
  EXPECT_EQ(json_depth(R"({"a":"[[[[[[","b":[{"c":"\"]]"}]})", 100), 3u);
  EXPECT_EQ(json::parse(s.handle(R"({"type":"stats","fps":[1,2,{"a":"[["}]})"))["type"], "ok");
  expect_error(s, "{\"type\":\"stats\",\"x\":\"" + std::string(kMaxMessageBytes, 'a') + "\"}");
}

TEST(StudioHostile, EveryTypeWithJunkFieldsGetsAReply) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  const std::string e = repeat("\xC3\xA9", 200);
  for (const std::string& type : message_types()) {
    if (type == "hello" || type == "mode") continue;  // these start the loop on a session
    for (const json& v : {json(e), json(1e308), json(-1), json::array({e}), json(nullptr)}) {
      json m{{"type", type}};
      for (const char* k : {"path", "points", "mesh", "ids", "value", "participant", "name",
                            "source", "model", "sys", "shape", "alpha", "x", "y", "z", "seq"})
        m[k] = v;
      std::string r;
      EXPECT_NO_THROW(r = s.handle(m.dump())) << type;
      if (!r.empty()) {
        EXPECT_FALSE(json::parse(r, nullptr, false).is_discarded()) << type;
      }
    }
  }
}

// Workspace writes: a symlink planted in the workspace under the temporary name the old code
// predicted (NAME.tmp.<pid>) or under the final name never makes a file appear outside.
TEST(StudioHostile, WritesDoNotFollowPlantedSymlinks) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  inhap::write_file_atomic((ws.root() / "s.json").string(), session_file(3));
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  ASSERT_EQ(json::parse(s.handle(R"({"type":"open_session","path":"s.json"})"))["type"], "samples");
  const std::string pid = std::to_string(::getpid());
  int k = 0;
  for (const std::string name : {"out.ply", "saved.json"}) {
    const fs::path outside = tmp.root() / ("outside-" + std::to_string(k++));
    fs::create_symlink(outside, ws.root() / (name + ".tmp." + pid));
    const std::string msg = name == "out.ply"
                                ? json{{"type", "export"}, {"points", name}}.dump()
                                : json{{"type", "save_session"}, {"path", name}}.dump();
    const json r = json::parse(s.handle(msg));
    EXPECT_EQ(r.value("type", ""), "ok") << r.dump();
    EXPECT_FALSE(fs::exists(fs::symlink_status(outside))) << name;
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(ws.root() / name))) << name;
  }
  // A symlink at the final name is replaced, not written through.
  const fs::path outside = tmp.root() / "outside-final";
  fs::create_symlink(outside, ws.root() / "final.json");
  EXPECT_EQ(json::parse(s.handle(R"({"type":"save_session","path":"final.json"})"))["type"], "ok");
  EXPECT_FALSE(fs::exists(fs::symlink_status(outside)));
  // A folder inside the workspace that is a symlink to one outside is refused.
  fs::create_directory(tmp.root() / "elsewhere");
  fs::create_directory_symlink(tmp.root() / "elsewhere", ws.root() / "sub");
  expect_error(s, R"({"type":"save_session","path":"sub/x.json"})");
  EXPECT_TRUE(fs::is_empty(tmp.root() / "elsewhere"));
}

// Reads: a symlink in the workspace to a file outside is refused, summary included, and nothing
// of the outside file comes back in the reply.
TEST(StudioHostile, ReadsDoNotFollowSymlinksSummaryIncluded) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  inhap::write_file_atomic((tmp.root() / "secret.csv").string(), "TOPSECRET,1,2\n");
  fs::create_symlink(tmp.root() / "secret.csv", ws.root() / "participant-777.csv");
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  const std::string r = s.handle(R"({"type":"summary"})");
  EXPECT_EQ(r.find("TOPSECRET"), std::string::npos) << r;
  EXPECT_EQ(json::parse(r).value("type", ""), "error") << r;
  fs::create_symlink(tmp.root() / "secret.csv", ws.root() / "s.json");
  const std::string r2 = s.handle(R"({"type":"open_session","path":"s.json"})");
  EXPECT_EQ(r2.find("TOPSECRET"), std::string::npos) << r2;
  EXPECT_EQ(json::parse(r2).value("type", ""), "error") << r2;
}
