// inhap/core/web_dir.hpp: where inhap looks for its folders, and the web folder it picks.
#include <gtest/gtest.h>

#include <filesystem>

#include "inhap/core/error.hpp"
#include "inhap/core/web_dir.hpp"

namespace inhap {
namespace {

namespace fs = std::filesystem;

TEST(WebDir, BesideProgramLooksBesideTheTestThenUpThenHere) {
  const std::vector<fs::path> c = beside_program("data");
  const fs::path exe_dir = fs::canonical("/proc/self/exe").parent_path();
  ASSERT_GE(c.size(), 3u);
  EXPECT_EQ(c[0], exe_dir / "data");
  EXPECT_EQ(c[1], exe_dir / "share/inhap/data");
  EXPECT_EQ(c[2], exe_dir.parent_path() / "data");
  EXPECT_EQ(c.back(), fs::current_path() / "data");
}

TEST(WebDir, GivenFolderIsTakenWhenItHasWhatIsAsked) {
  const std::string src = INHAP_SOURCE_DIR;
  const auto has_template = [](const fs::path& d) {
    return fs::exists(d / "report_template.html");
  };
  EXPECT_EQ(find_web_dir(src + "/web", has_template, "the template"), src + "/web");
  EXPECT_THROW(find_web_dir(src + "/docs", has_template, "the template"), Error);
}

}  // namespace
}  // namespace inhap
