// The program's error contract (docs/architecture.md): "inhap: error: <one line>", exit 1 for
// bad input, 2 for bad flags; a mistyped subcommand gets a suggestion; help shows defaults.
#include <gtest/gtest.h>

#include <string>

#include "support/run_cli.hpp"

namespace inhap {
namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

void expect_flag_error(const std::string& args, const std::string& part) {
  const auto r = test::run_cli(args);
  EXPECT_EQ(r.status, 2) << args << "\n" << r.out;
  EXPECT_EQ(r.out.rfind("inhap: error: ", 0), 0u) << args << "\n" << r.out;
  EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "one line: " << r.out;
  EXPECT_TRUE(has(r.out, part)) << args << "\n" << r.out;
}

TEST(CliErrors, ParseErrorsArePrefixedAndExitTwo) {
  expect_flag_error("mesh info", "");  // missing positional/required
  expect_flag_error("lab record --scene dome --out x.csv --seconds abc", "--seconds");
  expect_flag_error("lab record --scene dome --out x.csv --bogus", "--bogus");
  expect_flag_error("lab record --scene dome --out x.csv --seconds 86400", "--seconds");
  expect_flag_error("shape contacts /nonexistent.csv --out x.ply", "nonexistent");
}

TEST(CliErrors, MistypedSubcommandGetsASuggestion) {
  expect_flag_error("lab recrod --scene dome", "did you mean 'inhap lab record'");
  expect_flag_error("modle train", "did you mean 'inhap model'");
  expect_flag_error("tca strok --mesh x", "did you mean 'inhap tca stroke'");
}

TEST(CliErrors, HelpAndVersionStillExitZero) {
  EXPECT_EQ(test::run_cli("--help").status, 0);
  EXPECT_EQ(test::run_cli("--version").status, 0);
  EXPECT_EQ(test::run_cli("lab record --help").status, 0);
}

TEST(CliHelp, DefaultsAreShown) {
  const auto rec = test::run_cli("lab record --help").out;
  for (const char* d : {"=60", "=explore", "=sphere", "=1"}) EXPECT_TRUE(has(rec, d)) << d << rec;
  const auto con = test::run_cli("shape contacts --help").out;
  for (const char* d : {"=estimate", "=0.2", "=100", "=auto"}) EXPECT_TRUE(has(con, d)) << d << con;
  // A switch whose default is on must not read as `{false}`.
  const auto tr = test::run_cli("model train --help").out;
  EXPECT_FALSE(has(tr, "{false}")) << tr;
  EXPECT_TRUE(has(tr, "--no-tail")) << tr;
}

}  // namespace
}  // namespace inhap
