// inhap demo: the self-contained HTML report. The page is web/report_template.html with the
// JavaScript libraries (plotly.js, three.js from web/node_modules, installed by ./run setup),
// the figures' data and web/report.js (the glue calling Plotly / three) inlined, so it opens
// offline. Units of the data: mm, N, s, N/mm.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/core/web_dir.hpp"
#include "inhap/report/report.hpp"

namespace inhap::report {
namespace {

namespace fs = std::filesystem;

const char* kPlotly = "node_modules/plotly.js-dist-min/plotly.min.js";
const char* kThreeModule = "node_modules/three/build/three.module.js";
const char* kThreeCore = "node_modules/three/build/three.core.js";
const char* kOrbit = "node_modules/three/examples/jsm/controls/OrbitControls.js";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot read", p.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v =
        (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    for (int k = 3; k >= 0; --k) out += t[(v >> (6 * k)) & 63];
  }
  if (i < in.size()) {
    const unsigned v =
        (unsigned char)in[i] << 16 | (i + 1 < in.size() ? (unsigned char)in[i + 1] << 8 : 0u);
    out += t[(v >> 18) & 63];
    out += t[(v >> 12) & 63];
    out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
}

void replace_marker(std::string& page, const std::string& marker, const std::string& content,
                    const std::string& template_path) {
  const auto p = page.find(marker);
  if (p == std::string::npos)
    throw Error(fmt::format("{}: expected the marker {}", template_path, marker));
  page.replace(p, marker.size(), content);
}

std::string data_url(const std::string& js) {
  return "data:text/javascript;base64," + base64(js);
}

// three.js is ES modules: three.module.js imports ./three.core.js, OrbitControls imports
// 'three'. An import map sends those specifiers to data: URLs of the files.
std::string import_map(const fs::path& web) {
  std::string module = slurp(web / kThreeModule);
  replace_all(module, "'./three.core.js'", "'three/core'");
  replace_all(module, "\"./three.core.js\"", "'three/core'");
  nlohmann::json m;
  m["imports"] = {{"three/core", data_url(slurp(web / kThreeCore))},
                  {"three", data_url(module)},
                  {"three/addons/controls/OrbitControls.js", data_url(slurp(web / kOrbit))}};
  return "<script type=\"importmap\">" + m.dump() + "</script>";
}

// Text safe inside a <script> element.
std::string script_safe(std::string s) {
  replace_all(s, "</", "<\\/");
  return s;
}

nlohmann::json report_json(const Options& o, const std::vector<StepRecord>& steps, double total,
                           double cpu) {
  nlohmann::json j;
  j["title"] = "inhap demo: the thesis on the virtual lab";
  j["quick"] = o.quick;
  j["seed"] = o.seed;
  j["physics"] = lab::to_string(o.physics);
  j["total_s"] = rnd(total, 1);
  j["cpu_s"] = rnd(cpu, 1);
  j["steps"] = nlohmann::json::array();
  for (const auto& s : steps) {
    nlohmann::json js = {{"name", s.step.name},
                         {"chapter", s.step.chapter},
                         {"title", s.step.title},
                         {"available", s.result.available},
                         {"note", s.result.note},
                         {"seconds", rnd(s.result.seconds, 1)},
                         {"cpu_seconds", rnd(s.result.cpu_seconds, 1)},
                         {"files", s.result.files}};
    js["rows"] = nlohmann::json::array();
    for (const auto& r : s.result.rows)
      js["rows"].push_back(
          {{"quantity", r.quantity}, {"measured", r.measured}, {"thesis", r.thesis}});
    js["figures"] = nlohmann::json::array();
    for (const auto& f : s.result.figures)
      js["figures"].push_back({{"id", f.id},
                               {"title", f.title},
                               {"caption", f.caption},
                               {"kind", f.kind},
                               {"spec", f.spec}});
    j["steps"].push_back(js);
  }
  return j;
}

bool has_template(const fs::path& d) {
  return fs::exists(d / "report_template.html");
}

}  // namespace

std::string find_web_dir(const std::string& given) {
  const std::string dir =
      inhap::find_web_dir(given, has_template, "the report template web/report_template.html");
  for (const char* lib : {kPlotly, kThreeModule, kThreeCore, kOrbit})
    if (!fs::exists(fs::path(dir) / lib))
      throw Error(fmt::format(
          "{}: the report's JavaScript libraries are missing (expected {}): run ./run setup "
          "(it runs npm ci --prefix web)",
          dir, lib));
  return dir;
}

void write_report(const Options& o, const std::string& web_dir,
                  const std::vector<StepRecord>& steps, double total, double cpu) {
  const fs::path web(web_dir), out(o.out);
  const nlohmann::json data = report_json(o, steps, total, cpu);
  const std::string tpl_path = (web / "report_template.html").string();
  std::string page = slurp(tpl_path);
  replace_marker(page, "<!--INHAP_PLOTLY-->",
                 "<script>" + script_safe(slurp(web / kPlotly)) + "</script>", tpl_path);
  replace_marker(page, "<!--INHAP_IMPORTMAP-->", import_map(web), tpl_path);
  replace_marker(page, "<!--INHAP_DATA-->",
                 "<script type=\"application/json\" id=\"inhap-data\">" + script_safe(data.dump()) +
                     "</script>",
                 tpl_path);
  replace_marker(page, "<!--INHAP_REPORT_JS-->",
                 "<script type=\"module\">" + script_safe(slurp(web / "report.js")) + "</script>",
                 tpl_path);
  write_file_atomic((out / "report.html").string(), page);

  // The summary for people who plot themselves.
  auto quote = [](std::string v) {
    replace_all(v, "\"", "\"\"");
    return "\"" + v + "\"";
  };
  std::string csv = "step,chapter,quantity,measured,thesis\n";
  for (const auto& s : steps)
    for (const auto& r : s.result.rows)
      csv += fmt::format("{},{},{},{},{}\n", quote(s.step.name), quote(s.step.chapter),
                         quote(r.quantity), quote(r.measured), quote(r.thesis));
  write_file_atomic((out / "summary.csv").string(), csv);
  nlohmann::json figs = nlohmann::json::object();
  for (const auto& s : data["steps"])
    for (const auto& f : s["figures"]) figs[f["id"].get<std::string>()] = f;
  write_file_atomic((out / "figures.json").string(), figs.dump() + "\n");
  nlohmann::json summary = data;
  for (auto& s : summary["steps"]) s.erase("figures");
  write_file_atomic((out / "summary.json").string(), summary.dump(2) + "\n");
}

}  // namespace inhap::report
