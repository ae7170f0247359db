// report::select_steps and report::run_steps: what `inhap demo` runs, without the program.
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/report/report.hpp"

namespace inhap::report {
namespace {

TEST(RunSteps, SelectKeepsThesisOrderAndRejectsUnknownNames) {
  const auto all = select_steps({});
  EXPECT_EQ(all.size(), all_steps().size());
  const auto two = select_steps({"strokes", "tap"});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].name, "tap");  // thesis order, not the order given
  EXPECT_EQ(two[1].name, "strokes");
  try {
    select_steps({"tap", "nope"});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--only: expected one of tap "), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("got 'nope'"), std::string::npos);
  }
}

TEST(RunSteps, RunsInOrderAndReports) {
  std::vector<std::string> ran, log, done;
  auto step = [&](const std::string& name, bool available) {
    return Step{name, "3", "title " + name, [&ran, name, available](const Context& c) {
                  ran.push_back(name);
                  c.progress(0.5, "half");
                  StepResult r;
                  r.available = available;
                  r.note = available ? "" : "no data";
                  return r;
                }};
  };
  std::vector<double> fractions;
  const Options o;
  const auto records = run_steps(
      o, {step("a", true), step("b", false)},
      [&](const std::string&, double f, double) { fractions.push_back(f); },
      [&](const std::string& what, double, double) { done.push_back(what); },
      [&](const std::string& line) { log.push_back(line); });
  EXPECT_EQ(ran, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[1].step.name, "b");
  EXPECT_GE(records[0].result.seconds, 0.0);
  EXPECT_EQ(done, (std::vector<std::string>{"a"}));  // a skipped step is not "done"
  ASSERT_EQ(log.size(), 4u);
  EXPECT_EQ(log[0], "[demo] step 1/2: a (thesis 3): title a\n");
  EXPECT_NE(log[3].find("[demo] b skipped (no data) in "), std::string::npos) << log[3];
  EXPECT_EQ(fractions.size(), 2u);
}

}  // namespace
}  // namespace inhap::report
