// sys.json: a finite but absurd number (f_limit 1e308 N) is refused naming the file; before,
// `sys table` and `sys proxy` accepted it.
#include <gtest/gtest.h>

#include <string>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/sys_model.hpp"
#include "support/temp_dir.hpp"

TEST(SysHuge, AnAbsurdElasticLimitIsRefusedNamingTheFile) {
  inhap::test::TempDir tmp;
  std::string text =
      inhap::read_file(std::string(INHAP_SOURCE_DIR) + "/tests/fuzz/corpus/sys/small.json");
  const std::string path = tmp.path("sys.json");
  inhap::write_file_atomic(path, text);
  EXPECT_NO_THROW((void)inhap::friction::read_sys_json(path));
  const auto at = text.find("\"f_limit\": 0.5");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 14, "\"f_limit\": 1e308");
  inhap::write_file_atomic(path, text);
  try {
    (void)inhap::friction::read_sys_json(path);
    FAIL() << "f_limit 1e308 accepted";
  } catch (const inhap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("sys.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("f_limit"), std::string::npos) << e.what();
  }
}
