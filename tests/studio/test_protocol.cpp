// inhap studio messages: malformed input gets an error reply and changes nothing
// (include/inhap/studio/protocol.hpp, session.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include "inhap/core/atomic_file.hpp"

#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/lab/scene.hpp"
#include "inhap/rendering/datasets.hpp"
#include "inhap/studio/display.hpp"
#include "inhap/studio/experiment_summary.hpp"
#include "inhap/studio/protocol.hpp"
#include "inhap/studio/session.hpp"
#include "support/temp_dir.hpp"

using namespace inhap::studio;
using nlohmann::json;

namespace test_protocol {

json reply(Session& s, const std::string& text) {
  return json::parse(s.handle(text));
}

// A session file with n samples (ids 0..n-1) on a plane z = 10.
std::string session_file(int n) {
  json pts = json::array();
  for (int i = 0; i < n; ++i)
    pts.push_back({{"id", i},
                   {"point", {i * 3.0, (i % 4) * 2.5, 10.0}},
                   {"threshold", {i * 3.0, (i % 4) * 2.5, 10.2}},
                   {"direction", {0, 0, 1}}});
  return json{{"format", "inhap-studio-session"}, {"version", 1}, {"samples", pts}}.dump();
}

TEST(StudioProtocol, ParseRefusesMalformedFrames) {
  for (const char* bad : {"", "{", "[1,2]", "42", "\"x\"", "{\"kind\":\"hello\"}", "{\"type\":7}",
                          "{\"type\":\"rm -rf\"}", "null"})
    EXPECT_THROW(parse_message(bad), ProtocolError) << bad;
  EXPECT_EQ(parse_message("{\"type\":\"hello\"}").type, "hello");
}

TEST(StudioProtocol, CheckedGettersRefuseWrongKindsAndRanges) {
  const Message m =
      parse_message(R"({"type":"probe","x":"1","y":1e300,"z":5,"seq":1.5,"ids":[1,"a"],"ok":1})");
  EXPECT_THROW(get_number(m, "x", -10, 10), ProtocolError);  // a string
  EXPECT_THROW(get_number(m, "z", -1, 1), ProtocolError);    // out of range
  EXPECT_THROW(get_number(m, "w", -1, 1), ProtocolError);    // missing
  EXPECT_THROW(get_number(m, "y", -1e4, 1e4), ProtocolError);
  EXPECT_THROW(get_integer(m, "seq", 0, 10), ProtocolError);  // not an integer
  EXPECT_THROW(get_integer_list(m, "ids", 0, 10, 5), ProtocolError);
  EXPECT_THROW(get_bool_or(m, "ok", false), ProtocolError);
  EXPECT_DOUBLE_EQ(get_number(m, "z", 0, 10), 5.0);
}

TEST(StudioSession, MalformedMessagesChangeNothing) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  inhap::write_file_atomic((ws.root() / "s.json").string(), session_file(12));
  std::vector<std::string> sent;
  StudioOptions o;
  Session s(o, ws, [&](const std::string& t) { sent.push_back(t); });  // not started: no loop
  EXPECT_EQ(reply(s, R"({"type":"open_session","path":"s.json"})")["type"], "samples");
  ASSERT_EQ(s.live_samples(), 12u);

  // Each is refused with an error reply naming the request; the samples stay as they were.
  const std::vector<std::string> bad = {
      "not json",
      R"({"type":"delete","ids":[0,99]})",  // 99 does not exist: 0 is not deleted either
      R"({"type":"delete","ids":[]})",
      R"({"type":"delete","ids":"0"})",
      R"({"type":"delete"})",
      R"({"type":"undo"})",  // nothing to undo
      R"({"type":"export","points":"../out.ply"})",
      R"({"type":"export","points":"/tmp/out.ply"})",
      R"({"type":"export","points":"out.txt"})",
      R"({"type":"open_session","path":"../s.json"})",
      R"({"type":"open_mesh","source":"elsewhere"})",
      R"({"type":"reconstruct","alpha":-1})",
      R"({"type":"answer","value":1})",         // no experiment
      R"({"type":"mode","mode":"palpating"})",  // internal: only palpate starts it
      R"({"type":"probe","x":1,"y":2,"z":"3","seq":1})",
  };
  for (const auto& text : bad) {
    const json r = reply(s, text);
    EXPECT_EQ(r["type"], "error") << text;
    EXPECT_FALSE(r["message"].get<std::string>().empty()) << text;
    EXPECT_EQ(s.live_samples(), 12u) << text;
  }
  EXPECT_FALSE(std::filesystem::exists(tmp.root() / "out.ply"));
  EXPECT_FALSE(std::filesystem::exists(ws.root() / "out.txt"));

  // The well-formed versions work: delete two, undo one, export the rest.
  EXPECT_EQ(reply(s, R"({"type":"delete","ids":[0,5]})")["type"], "samples");
  EXPECT_EQ(s.live_samples(), 10u);
  EXPECT_EQ(reply(s, R"({"type":"undo"})")["type"], "samples");
  EXPECT_EQ(s.live_samples(), 12u);
  EXPECT_EQ(reply(s, R"({"type":"delete","ids":[3]})")["type"], "samples");
  const json ex = reply(s, R"({"type":"export","points":"out.ply"})");
  EXPECT_EQ(ex["type"], "ok") << ex.dump();
  EXPECT_EQ(ex["points"], 11);
  EXPECT_TRUE(std::filesystem::exists(ws.root() / "out.ply"));
}

TEST(StudioExperiment, SavedAnswersAreScoredByTheLibrary) {
  // Truth from Table 5.1 via the library; answers written as the Experiment view writes them.
  inhap::test::TempDir tmp;
  const auto truth = [](int m) { return int(inhap::rendering::true_shape_class(m)); };
  std::string csv =
      "# comment\nparticipant,session,trial,algorithm,task,layout_seed,cell,model,label,truth,"
      "correct,t\n";
  // trial 0 (TCA, shape): models 1-3 right, model 4 wrong; trial 1 (TCA, shape): model 5 right.
  for (int m = 0; m < 4; ++m)
    csv += fmt::format("2,0,0,tca,shape,11,{},{},{},0,0,1.0\n", m, m + 1,
                       m < 3 ? truth(m) : (truth(m) + 1) % 3);
  csv += fmt::format("2,0,1,tca,shape,12,7,5,{},0,0,2.0\n", truth(4));
  inhap::write_file_atomic(tmp.path("participant-002.csv"), csv);
  inhap::write_file_atomic(tmp.path("other.csv"), "not answers\n");  // ignored
  const json s = inhap::studio::summarize_answers(tmp.root());
  EXPECT_EQ(s["trials"], 2);
  ASSERT_EQ(s["conditions"].size(), 1u);
  const json& c = s["conditions"][0];
  EXPECT_EQ(c["algorithm"], inhap::rendering::to_string(inhap::rendering::Algorithm::kTCA));
  EXPECT_DOUBLE_EQ(c["mean"].get<double>(), (3 + 1) / 2.0);  // 3 then 1 correct of 25
  EXPECT_DOUBLE_EQ(c["model_ratio"][0].get<double>(), 0.5);  // right in trial 0 only
  EXPECT_DOUBLE_EQ(c["model_ratio"][3].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(c["model_ratio"][4].get<double>(), 0.5);

  inhap::write_file_atomic(tmp.path("participant-003.csv"), "3,0,0,tca,shape,1,0,26,1,0,0,1\n");
  try {
    inhap::studio::summarize_answers(tmp.root());
    ADD_FAILURE() << "model 26 accepted";
  } catch (const inhap::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("participant-003.csv"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 1u);
  }
}

TEST(StudioSession, OpensADataDrivenModelOrNothing) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  const std::string corpus = std::string(INHAP_SOURCE_DIR) + "/tests/fuzz/corpus/";
  inhap::write_file_atomic((ws.root() / "model.json").string(),
                           inhap::read_file(corpus + "model/small.json"));
  inhap::write_file_atomic((ws.root() / "sys.json").string(),
                           inhap::read_file(corpus + "sys/small.json"));
  inhap::TriMesh plane;  // a 100 mm square at z = 0
  plane.positions = {{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}};
  plane.triangles = {{0, 1, 2}, {0, 2, 3}};
  inhap::write_mesh((ws.root() / "plane.ply").string(), plane);
  StudioOptions o;
  Session s(o, ws, [](const std::string&) {});

  // A missing file: refused, and TCA-MESH can still be chosen (nothing data-driven was opened).
  json r = reply(
      s,
      R"({"type":"open_mesh","source":"model","model":"model.json","sys":"none.json","shape":"plane.ply"})");
  EXPECT_EQ(r["type"], "error") << r.dump();
  EXPECT_EQ(reply(s, R"({"type":"algorithm","name":"tca"})")["type"], "ok");

  r = reply(
      s,
      R"({"type":"open_mesh","source":"model","model":"model.json","sys":"sys.json","shape":"plane.ply"})");
  ASSERT_EQ(r["type"], "mesh") << r.dump();
  EXPECT_EQ(r["algorithm"], "data-driven");
  EXPECT_EQ(r["faces"].size(), 6u);  // the plane's two triangles
  // now TCA-MESH / CBA are refused: the shape carries no stiffness map
  EXPECT_EQ(reply(s, R"({"type":"algorithm","name":"cba"})")["type"], "error");
  // back to a stiffness mesh
  EXPECT_EQ(reply(s, R"({"type":"open_mesh","source":"study25"})")["algorithm"], "tca");
}

TEST(StudioSession, PreviewShowsTheOutlierAndTheProjectionApplyAndUndo) {
  // 60 samples scattered on the plane z = 10 with a +-0.2 mm zig-zag, and one 30 mm above it
  // (id 60).
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  json pts = json::array();
  for (int i = 0; i < 60; ++i)
    pts.push_back({{"id", i},
                   {"point",
                    {(i % 10) * 3.0 + 1.2 * std::sin(i * 1.7),
                     (i / 10) * 3.0 + 1.2 * std::cos(i * 2.3), 10.0 + ((i % 2) ? 0.2 : -0.2)}},
                   {"threshold", {0, 0, 0}},
                   {"direction", {0, 0, 1}}});
  pts.push_back({{"id", 60},
                 {"point", {9.0, 9.0, 40.0}},
                 {"threshold", {0, 0, 0}},
                 {"direction", {0, 0, 1}}});
  inhap::write_file_atomic(
      (ws.root() / "p.json").string(),
      json{{"format", "inhap-studio-session"}, {"version", 1}, {"samples", pts}}.dump());
  StudioOptions o;
  Session s(o, ws, [](const std::string&) {});
  ASSERT_EQ(reply(s, R"({"type":"open_session","path":"p.json"})")["type"], "samples");
  const json p = reply(s, R"({"type":"preview"})");
  ASSERT_EQ(p["type"], "preview") << p.dump();
  EXPECT_EQ(p["outliers"], json::array({60}));
  ASSERT_EQ(p["moves"].size(), 60u);
  // The jet through a zig-zag about z = 10 puts the samples nearer to the plane.
  double before = 0, after = 0;
  for (const auto& m : p["moves"]) {
    const long id = m["id"];
    before += 0.2;
    after += std::abs(m["to"][2].get<double>() - 10.0);
    EXPECT_LT(id, 60);
  }
  EXPECT_LT(after, 0.5 * before);
  EXPECT_EQ(s.live_samples(), 61u);  // a preview changes nothing

  const json a = reply(s, R"({"type":"apply_preview"})");
  ASSERT_EQ(a["type"], "samples");
  EXPECT_EQ(s.live_samples(), 60u);
  double z0 = 0;
  for (const auto& q : a["samples"])
    if (q["id"] == 0) z0 = q["point"][2];
  EXPECT_NEAR(z0, p["moves"][0]["to"][2].get<double>(), 1e-12);
  const json u = reply(s, R"({"type":"undo"})");
  EXPECT_EQ(s.live_samples(), 61u);
  double z0_back = 0;
  for (const auto& q : u["samples"])
    if (q["id"] == 0) z0_back = q["point"][2];
  EXPECT_DOUBLE_EQ(z0_back, 9.8);  // undo puts it back
}

// `hello` broadcasts the lab object's top view for the page: its positions to the micrometre
// (each number at most 3 decimals, not a float's 16 digits), the same mesh either way.
TEST(StudioSession, HelloSendsTheObjectsTopViewToTheMicrometre) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  std::vector<std::string> sent;
  Session s(StudioOptions{}, ws, [&sent](const std::string& m) { sent.push_back(m); });
  EXPECT_EQ(reply(s, R"({"type":"hello"})")["type"], "hello");
  const std::string* text = nullptr;
  for (const std::string& m : sent)
    if (json::parse(m)["type"] == "mesh") text = &m;
  ASSERT_NE(text, nullptr);
  const json mesh = json::parse(*text);
  EXPECT_EQ(mesh["role"], "object");
  const inhap::TriMesh truth = top_view_mesh(inhap::lab::builtin_scene("dome").object.shape());
  const auto& v = mesh["vertices"];
  ASSERT_EQ(v.size(), 3 * truth.num_vertices());
  ASSERT_EQ(mesh["faces"].size(), 3 * truth.num_triangles());
  double worst = 0;
  for (std::size_t i = 0; i < truth.num_vertices(); ++i)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(v[3 * i + k].get<double>() - truth.positions[i][k]));
  EXPECT_LE(worst, 0.5e-3 + 1e-9);
  EXPECT_GT(worst, 0.0);  // rounded, so not all exact
  // No number in the message with more than 3 digits after the point.
  const std::string body = text->substr(text->find("\"vertices\""));
  std::size_t longest = 0;
  for (std::size_t i = 0; i < body.size(); ++i)
    if (body[i] == '.') {
      std::size_t n = 0;
      while (i + 1 + n < body.size() && std::isdigit(static_cast<unsigned char>(body[i + 1 + n])))
        ++n;
      longest = std::max(longest, n);
    }
  EXPECT_LE(longest, 3u);
}

// The servo request: no loop before start(); then the running loop's counts, read while it runs
// (ticks advance between two requests).
TEST(StudioSession, ServoRequestReportsTheRunningLoop) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  StudioOptions o;
  Session s(o, ws, [](const std::string&) {});
  const json idle = reply(s, R"({"type":"servo"})");
  EXPECT_EQ(idle["type"], "servo");
  EXPECT_EQ(idle["running"], false);
  s.start(0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const json a = reply(s, R"({"type":"servo"})");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const json b = reply(s, R"({"type":"servo"})");
  s.stop();
  ASSERT_EQ(a["type"], "servo") << a.dump();
  EXPECT_EQ(a["running"], true);
  EXPECT_GT(b["ticks"].get<std::uint64_t>(), a["ticks"].get<std::uint64_t>());
  EXPECT_GE(b["overruns"].get<std::uint64_t>(), a["overruns"].get<std::uint64_t>());
  EXPECT_EQ(a["period_us"], 1000.0);
  EXPECT_TRUE(a["rt"].is_string());
}

// A session file from the workspace is hostile too: ids that repeat, overflow (id + 1 was
// computed from a long) or are not integers, and flags that are not booleans are refused with
// the file's name, and the samples stay as they were.
TEST(StudioSession, OpenSessionRefusesBadIdsAndFlags) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  inhap::write_file_atomic((ws.root() / "s.json").string(), session_file(3));
  Session s(StudioOptions{}, ws, [](const std::string&) {});
  ASSERT_EQ(reply(s, R"({"type":"open_session","path":"s.json"})")["type"], "samples");
  const std::string good = session_file(1);
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  const std::pair<std::string, std::string> bad[] = {
      {R"({"format":"inhap-studio-session","samples":[{"id":1,"point":[0,0,0],"threshold":[0,0,0],"direction":[0,0,1]},{"id":1,"point":[0,0,0],"threshold":[0,0,0],"direction":[0,0,1]}]})",
       "appears twice"},
      {with(R"("id":0)", R"("id":9223372036854775807)"), "outside 0..2^52"},
      {with(R"("id":0)", R"("id":-1)"), "outside 0..2^52"},
      {with(R"("id":0)", R"("id":0.5)"), "integer"},
      {with(R"("id":0)", R"("id":0,"deleted":"yes")"), "true or false"},
      {std::string(100, '[') + std::string(100, ']'), "session file"},
  };
  for (const auto& [text, needle] : bad) {
    inhap::write_file_atomic((ws.root() / "b.json").string(), text);
    const json r = reply(s, R"({"type":"open_session","path":"b.json"})");
    EXPECT_EQ(r["type"], "error") << text;
    const std::string msg = r.value("message", "");
    EXPECT_NE(msg.find("b.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    EXPECT_EQ(s.live_samples(), 3u);
  }
}
}  // namespace test_protocol
