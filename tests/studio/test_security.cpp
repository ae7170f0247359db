// inhap studio access rules (include/inhap/studio/security.hpp): the token, Host and Origin checks
// and the workspace path guard.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>

#include <filesystem>
#include <fstream>
#include <set>

#include "inhap/core/error.hpp"
#include "inhap/studio/security.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace inhap::studio;

TEST(StudioToken, IsThirtyTwoHexDigitsAndFresh) {
  std::set<std::string> seen;
  for (int i = 0; i < 50; ++i) {
    const std::string t = make_token();
    ASSERT_EQ(t.size(), 32u);
    for (char c : t) EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(c))) << t;
    seen.insert(t);
  }
  EXPECT_EQ(seen.size(), 50u);  // 128 random bits: a repeat would mean no randomness
}

TEST(StudioToken, MatchesOnlyTheExactToken) {
  const std::string t = make_token();
  EXPECT_TRUE(token_matches(t, t));
  std::string other = t;
  other.back() = other.back() == 'a' ? 'b' : 'a';
  EXPECT_FALSE(token_matches(other, t));
  EXPECT_FALSE(token_matches(t.substr(0, 31), t));
  EXPECT_FALSE(token_matches("", t));
  EXPECT_FALSE(token_matches("", ""));  // a server without a token lets nobody in
}

TEST(StudioToken, FromQueryOrCookie) {
  const std::string t = make_token();
  EXPECT_TRUE(request_authorized("token=" + t, "", t));
  EXPECT_TRUE(request_authorized("a=1&token=" + t + "&b=2", "", t));
  EXPECT_TRUE(request_authorized("", "x=1; inhap_studio=" + t, t));
  EXPECT_FALSE(request_authorized("", "", t));
  EXPECT_FALSE(request_authorized("token=", "", t));
  EXPECT_FALSE(request_authorized("xtoken=" + t, "", t));
  EXPECT_FALSE(request_authorized("", "inhap_studiox=" + t, t));
  EXPECT_FALSE(request_authorized("token=" + t + "0", "", t));
}

TEST(StudioHostOrigin, OnlyTheLoopbackServer) {
  EXPECT_TRUE(host_allowed("127.0.0.1:8765", 8765));
  EXPECT_TRUE(host_allowed("localhost:8765", 8765));
  EXPECT_FALSE(host_allowed("127.0.0.1:8766", 8765));
  EXPECT_FALSE(host_allowed("evil.example:8765", 8765));  // DNS rebinding
  EXPECT_FALSE(host_allowed("", 8765));
  EXPECT_TRUE(origin_allowed("", 8765, false));  // a same-origin navigation sends no Origin
  EXPECT_FALSE(origin_allowed("", 8765, true));  // a WebSocket upgrade must
  EXPECT_TRUE(origin_allowed("http://127.0.0.1:8765", 8765, true));
  EXPECT_TRUE(origin_allowed("http://localhost:8765", 8765, true));
  EXPECT_FALSE(origin_allowed("http://evil.example", 8765, false));
  EXPECT_FALSE(origin_allowed("https://127.0.0.1:8765", 8765, true));
  EXPECT_FALSE(origin_allowed("http://127.0.0.1:8765.evil", 8765, true));
  EXPECT_FALSE(origin_allowed("null", 8765, false));
}

TEST(StudioWorkspace, AcceptsPathsInside) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  const fs::path root = fs::canonical(tmp.root() / "ws");
  EXPECT_EQ(ws.resolve("a.ply"), root / "a.ply");
  EXPECT_EQ(ws.resolve("sub/b.ply"), root / "sub/b.ply");
  EXPECT_EQ(ws.resolve("./c.csv"), root / "c.csv");
}

TEST(StudioWorkspace, RefusesEscapes) {
  inhap::test::TempDir tmp;
  const Workspace ws(tmp.root() / "ws");
  for (const char* bad :
       {"", "../x.ply", "a/../../x.ply", "sub/..", "/etc/passwd", "..", "a\\b.ply", ".", "sub/"})
    EXPECT_THROW(ws.resolve(bad), inhap::Error) << bad;
  EXPECT_THROW(ws.resolve(std::string("a\0b", 3)), inhap::Error);
  EXPECT_THROW(ws.resolve(std::string(300, 'x')), inhap::Error);
}

TEST(StudioWorkspace, RefusesSymlinksLeadingOutside) {
  inhap::test::TempDir tmp;
  fs::create_directories(tmp.root() / "outside");
  std::ofstream(tmp.root() / "outside/secret.txt") << "x";
  const Workspace ws(tmp.root() / "ws");
  fs::create_directory_symlink(tmp.root() / "outside", tmp.root() / "ws/link");
  fs::create_symlink(tmp.root() / "outside/secret.txt", tmp.root() / "ws/file.txt");
  fs::create_directories(tmp.root() / "ws/inner");
  fs::create_directory_symlink(tmp.root() / "ws/inner", tmp.root() / "ws/inlink");
  EXPECT_THROW(ws.resolve("link/secret.txt"), inhap::Error);
  EXPECT_THROW(ws.resolve("link/new.ply"), inhap::Error);
  EXPECT_THROW(ws.resolve("file.txt"), inhap::Error);
  // a symlink that stays inside is fine
  EXPECT_EQ(ws.resolve("inlink/x.ply"), fs::canonical(tmp.root() / "ws/inner") / "x.ply");
}

TEST(StudioWorkspace, OpensBeneathWithoutFollowingAnySymlink) {
  inhap::test::TempDir tmp;
  fs::create_directories(tmp.root() / "outside");
  std::ofstream(tmp.root() / "outside/secret.txt") << "secret";
  const Workspace ws(tmp.root() / "ws");
  fs::create_directories(tmp.root() / "ws/inner");
  std::ofstream(tmp.root() / "ws/inner/ok.txt") << "fine";
  fs::create_directory_symlink(tmp.root() / "outside", tmp.root() / "ws/link");
  fs::create_symlink(tmp.root() / "outside/secret.txt", tmp.root() / "ws/file.txt");
  fs::create_directory_symlink(tmp.root() / "ws/inner", tmp.root() / "ws/inlink");
  fs::create_symlink(tmp.root() / "ws/inner/ok.txt", tmp.root() / "ws/inside.txt");
  EXPECT_EQ(ws.read("inner/ok.txt"), "fine");
  // Every symlink is refused, also one that stays inside, for reading and for writing.
  for (const char* bad : {"link/secret.txt", "file.txt", "inlink/ok.txt", "inside.txt"}) {
    EXPECT_THROW((void)ws.read(bad), inhap::Error) << bad;
    EXPECT_THROW((void)ws.input(bad), inhap::Error) << bad;
  }
  EXPECT_THROW(ws.write("link/new.txt", "x"), inhap::Error);
  EXPECT_THROW(ws.write("inlink/new.txt", "x"), inhap::Error);
  EXPECT_FALSE(fs::exists(tmp.root() / "outside/new.txt"));
  // The refusal names the path as given and not what the link points to.
  try {
    (void)ws.read("file.txt");
  } catch (const inhap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("file.txt"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("secret"), std::string::npos) << e.what();
  }
  // Writing through output(): the file lands in the workspace, errors name it as given.
  ws.write("inner/new.txt", "n");
  EXPECT_EQ(ws.read("inner/new.txt"), "n");
  const WorkspacePath out = ws.output("inner/x.txt");
  EXPECT_EQ(out.tidy(out.path() + ": failed"), "inner/x.txt: failed");
  const auto names = ws.list();
  EXPECT_NE(std::find(names.begin(), names.end(), "file.txt"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "inner"), names.end());
}
