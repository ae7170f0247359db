// AtomicFile's temporary: an unpredictable name, created exclusively, never through a link.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>

#include "inhap/core/atomic_file.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;

TEST(AtomicFileLinks, APlantedLinkAtThePredictableTemporaryIsNotWrittenThrough) {
  inhap::test::TempDir tmp;
  fs::create_directory(tmp.root() / "ws");
  const fs::path target = tmp.root() / "ws/out.txt";
  const fs::path outside = tmp.root() / "outside.txt";
  // The name the old code used: <path>.tmp.<pid>.
  fs::create_symlink(outside, target.string() + ".tmp." + std::to_string(::getpid()));
  inhap::write_file_atomic(target.string(), "hello\n");
  EXPECT_FALSE(fs::exists(fs::symlink_status(outside)));
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(target)));
  EXPECT_EQ(inhap::read_file(target.string()), "hello\n");
}

TEST(AtomicFileLinks, TemporaryNamesAreRandomAndCleanedUp) {
  inhap::test::TempDir tmp;
  const std::string path = tmp.path("a.txt");
  std::set<std::string> names;
  for (int i = 0; i < 20; ++i) {
    inhap::AtomicFile f(path);
    for (const auto& e : fs::directory_iterator(tmp.root()))
      if (e.path().filename().string().rfind("a.txt.tmp.", 0) == 0)
        names.insert(e.path().filename().string());
  }  // destroyed without commit: removed
  EXPECT_EQ(names.size(), 20u);
  EXPECT_TRUE(fs::is_empty(tmp.root()));
}

TEST(AtomicFileLinks, ATransactionReplacesALinkAtTheFinalNameWithoutFollowingIt) {
  inhap::test::TempDir tmp;
  const fs::path outside = tmp.root() / "outside.txt";
  inhap::write_file_atomic(outside.string(), "keep\n");
  fs::create_symlink(outside, tmp.root() / "b.txt");
  {
    inhap::OutputTransaction tx;
    inhap::write_file_atomic(tmp.path("b.txt"), "new\n");
    tx.commit();
  }
  EXPECT_EQ(inhap::read_file(outside.string()), "keep\n");
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(tmp.root() / "b.txt")));
  EXPECT_EQ(inhap::read_file(tmp.path("b.txt")), "new\n");
}
