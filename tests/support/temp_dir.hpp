// A temporary directory for one test, removed when it goes out of scope.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace inhap::test {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "inhap";
    for (auto& c : name)
      if (c == '/') c = '_';
    std::string templ =
        (std::filesystem::temp_directory_path() / ("inhap-" + name + "-XXXXXX")).string();
    if (!::mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
    root_ = templ;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(root_, ec);
  }
  const std::filesystem::path& root() const { return root_; }
  std::string path(const std::string& name) const { return (root_ / name).string(); }

 private:
  std::filesystem::path root_;
};

/// Folder of the shared real data (bunny/, headsq/, afm-topography/), from INHAP_SHARED_DATA
/// in the environment or the build's default. Tests GTEST_SKIP() when a file is absent.
inline std::string shared_data(const std::string& rel) {
  const char* env = std::getenv("INHAP_SHARED_DATA");
  return std::string(env ? env : INHAP_SHARED_DATA) + "/" + rel;
}

}  // namespace inhap::test
