// `inhap demo` report in headless Chromium: the whole quick demo (about 10 s of CPU) writes
// out/report.html; Chromium opens it offline, the report's glue checks that every figure
// drew something (plotly: trace paths or table cells in its svg; three.js: vertices and
// non-background pixels in its canvas, counted into data-marks) and collects console errors into
// document.title, which the test reads back with --dump-dom. A screenshot goes to
// out/report-test/report.png for people to look at.
// Skips when chromium is not installed (./run setup installs it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool have_chromium() {
  return std::system("command -v chromium >/dev/null 2>&1") == 0;
}

// Source root of the project.
fs::path source_root() {
  // Absolute, from CMake (not __FILE__: a compiler cache may make that relative).
  return fs::path(INHAP_SOURCE_DIR);
}

std::string chromium(const std::string& profile, const std::string& extra) {
  return "chromium --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader "
         "--use-angle=swiftshader --disable-quic --no-first-run --disable-background-networking "
         "--disable-component-update --disable-sync --disable-default-apps "
         "--disable-extensions --user-data-dir=" +
         profile + " --virtual-time-budget=60000 " + extra;
}

// The page's DOM after its scripts ran (stdout of --dump-dom).
std::string dump_dom(const std::string& profile, const std::string& html) {
  const std::string cmd = chromium(profile, "--dump-dom file://" + html) + " 2>/dev/null";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  std::string out;
  if (!pipe) return out;
  char buf[65536];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  ::pclose(pipe);
  return out;
}

std::string title_of(const std::string& dom) {
  std::smatch m;
  static const std::regex re("<title>([^<]*)</title>");
  return std::regex_search(dom, m, re) ? m[1].str() : std::string("(no title)");
}

// The k-th number of the "measured" cell of the summary row whose quantity starts with `q`
// (NaN when absent).
double measured(const nlohmann::json& summary, const std::string& q, int k = 0) {
  for (const auto& step : summary["steps"])
    for (const auto& row : step["rows"]) {
      if (row["quantity"].get<std::string>().rfind(q, 0) != 0) continue;
      std::istringstream in(row["measured"].get<std::string>());
      double v = std::nan("");
      std::string slash;
      for (int i = 0; i <= k; ++i) {
        if (i > 0) in >> slash;
        in >> v;
      }
      return in ? v : std::nan("");
    }
  ADD_FAILURE() << "no summary row " << q;
  return std::nan("");
}

// One test (one demo run): ctest runs each test in its own process.
TEST(Report, EveryFigureDrawsWithoutConsoleErrorsAndTheCheckCanFail) {
  if (!have_chromium()) GTEST_SKIP() << "chromium not installed (./run setup installs it)";
  const fs::path out = source_root() / "out" / "report-test";
  fs::remove_all(out);
  const auto run = inhap::test::run_cli("demo --quick --out " + out.string());
  ASSERT_EQ(run.status, 0) << run.out;
  inhap::test::TempDir profile;
  const fs::path html = out / "report.html";
  ASSERT_TRUE(fs::exists(html));
  const std::string dom = dump_dom(profile.path("p"), html.string());
  const std::string title = title_of(dom);
  // The demo wrote these figures; the page must have drawn all of them.
  const auto figures = nlohmann::json::parse(slurp(out / "figures.json"));
  EXPECT_EQ(title, "REPORT_OK n_figures=" + std::to_string(figures.size())) << title;
  // The thesis figures of every step run, each with something drawn in its div.
  for (const char* id : {"fig3_2", "fig3_4", "fig3_6", "table3_1", "fig4_7", "fig4_8", "fig4_12",
                         "fig4_13", "fig4_14", "fig5_7_3d", "fig5_10", "fig5_11"})
    EXPECT_TRUE(figures.contains(id)) << id;
  bool has_three = false;
  for (const auto& [id, f] : figures.items()) {
    const std::regex re("id=\"fig-" + id + "\"[^>]*data-marks=\"([0-9]+)\"");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(dom, m, re)) << id << " has no data-marks";
    EXPECT_GT(std::stol(m[1].str()), 0) << id << " drew nothing";
    has_three |= f["kind"] == "three";
  }
  EXPECT_TRUE(has_three);
  // Every step's module is in the build: nothing is marked missing.
  EXPECT_EQ(dom.find("not available in this build"), std::string::npos);
  // The summary answers the thesis figures of the chapter-3/4 steps, and against the lab's
  // ground truth they are what the modules promise (docs/shape-modeling.md,
  // docs/sliding-yield-surface.md, docs/force-model.md): reconstructions within the thesis'
  // 2-3 mm, elastic limits within 10 % of mu f_N, proxy within 0.3 mm, RE below the thesis' dome.
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_LT(measured(summary, "dome (60 taps): Hausdorff"), 3.0);
  EXPECT_LT(measured(summary, "elastic limit vs true mu f_N"), 0.10);
  EXPECT_LT(measured(summary, "proxy q vs true anchor"), 0.3);
  EXPECT_LT(measured(summary, "dome: relative error RE", 1), 0.3);
  EXPECT_LT(measured(summary, "dome: force RMSE"), 1.0);

  // A screenshot for people.
  const fs::path png = out / "report.png";
  const std::string shot =
      chromium(profile.path("s"), "--screenshot=" + png.string() +
                                      " --window-size=1400,3000 file://" + html.string()) +
      " >/dev/null 2>&1";
  EXPECT_EQ(std::system(shot.c_str()), 0);
  EXPECT_TRUE(fs::exists(png) && fs::file_size(png) > 10000);

  // The check must be able to fail: the same report with one console error added.
  std::string page = slurp(html);
  const auto body = page.rfind("</body>");
  ASSERT_NE(body, std::string::npos);
  page.insert(body, "<script>console.error('injected failure');</script>");
  const std::string broken = profile.path("broken.html");
  std::ofstream(broken) << page;
  const std::string bad = title_of(dump_dom(profile.path("q"), broken));
  EXPECT_EQ(bad.rfind("REPORT_FAIL", 0), 0u) << bad;
  EXPECT_NE(bad.find("injected failure"), std::string::npos) << bad;

  // ... and it must notice figures that draw nothing: the same report with the traces of the
  // first plotly figure emptied and the first three.js mesh moved out of the camera's view
  // (edited in the page's data before report.js, a deferred module, reads it).
  page = slurp(html);
  page.insert(page.rfind("</body>"), R"(<script>
    const node = document.getElementById("inhap-data"), data = JSON.parse(node.textContent);
    const figs = data.steps.flatMap(s => s.figures);
    figs.find(f => f.kind === "plotly").spec.data = [{type: "scatter", x: [], y: []}];
    const mesh = figs.find(f => f.kind === "three").spec;
    mesh.meshes = [{positions: [], colors: [], indices: []}];
    mesh.lines = [];
    node.textContent = JSON.stringify(data);
  </script>)");
  const std::string empty = profile.path("empty.html");
  std::ofstream(empty) << page;
  const std::string none = title_of(dump_dom(profile.path("e"), empty));
  EXPECT_EQ(none.rfind("REPORT_FAIL", 0), 0u) << none;
  EXPECT_NE(none.find("plotly figure without traces"), std::string::npos) << none;
  EXPECT_NE(none.find("three.js figure without vertices"), std::string::npos) << none;
}

TEST(ReportLibraries, MissingLibrariesSayRunSetup) {
  inhap::test::TempDir dir;
  fs::create_directories(dir.path("web"));
  std::ofstream(dir.path("web/report_template.html")) << "<html></html>";
  const auto r = inhap::test::run_cli("demo --quick --only tap --web-dir " + dir.path("web") +
                                      " --out " + dir.path("out"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("./run setup"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path("out/report.html")));
}

}  // namespace
