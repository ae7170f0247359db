#include "inhap/lab/recorder.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <memory>

#include "inhap/core/error.hpp"

namespace inhap::lab {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const Vec3 kNaN3 = Vec3::Constant(kNaN);
}  // namespace

TickLogger::TickLogger(const SimDevice& device, std::size_t reserve_ticks)
    : dev_(device), comp_cfg_(CompensatorConfig::from(device.info())) {
  // A correctly configured logger removes exactly what the raw reading contains.
  comp_cfg_.gravity = device.params().gravity;
  comp_cfg_.inertia = device.params().inertia;
  auto& r = out_.rec;
  r.t.reserve(reserve_ticks);
  r.p.reserve(reserve_ticks);
  r.f.reserve(reserve_ticks);
  for (auto* v : {&rfx_, &rfy_, &rfz_}) v->reserve(reserve_ticks);
  auto& tr = out_.truth;
  tr.t.reserve(reserve_ticks);
  tr.contact.reserve(reserve_ticks);
  tr.tap.reserve(reserve_ticks);
  tr.tc.reserve(reserve_ticks);
  tr.c.reserve(reserve_ticks);
  tr.anchor.reserve(reserve_ticks);
  tr.force.reserve(reserve_ticks);
  tr.k.reserve(reserve_ticks);
  tr.mu.reserve(reserve_ticks);
}

void TickLogger::sample() {
  const double t = dev_.time();
  const Vec3 p = dev_.position();
  const Vec3 raw = dev_.force_sensor();
  auto& r = out_.rec;
  r.t.push_back(t);
  r.p.push_back(p);
  r.f.push_back(compensate_step(comp_cfg_, comp_, p, raw));
  rfx_.push_back(raw.x());
  rfy_.push_back(raw.y());
  rfz_.push_back(raw.z());

  const ContactState& cs = dev_.contact();
  auto& tr = out_.truth;
  tr.t.push_back(t);
  tr.contact.push_back(cs.in_contact ? 1 : 0);
  if (cs.in_contact) {
    if (cs.episode != last_episode_) {
      last_episode_ = cs.episode;
      ++taps_;
    }
    tr.tap.push_back(taps_ - 1);
    tr.tc.push_back(cs.start_time);
    tr.c.push_back(cs.start_point);
    tr.anchor.push_back(cs.proxy);
    tr.force.push_back(cs.force);
    tr.k.push_back(cs.law.effective_stiffness(5.0));
    tr.mu.push_back(cs.law.mu);
  } else {
    tr.tap.push_back(-1);
    tr.tc.push_back(kNaN);
    tr.c.push_back(kNaN3);
    tr.anchor.push_back(kNaN3);
    tr.force.push_back(Vec3::Zero());
    tr.k.push_back(kNaN);
    tr.mu.push_back(kNaN);
  }
}

LabRecording TickLogger::take() {
  out_.rec.extra_names = {"rfx", "rfy", "rfz"};
  out_.rec.extra = {std::move(rfx_), std::move(rfy_), std::move(rfz_)};
  LabRecording out = std::move(out_);
  out_ = LabRecording{};
  rfx_.clear(), rfy_.clear(), rfz_.clear();
  return out;
}

std::string truth_path_for(const std::string& csv_path) {
  const std::string ext = ".csv";
  if (csv_path.size() > ext.size() &&
      csv_path.compare(csv_path.size() - ext.size(), ext.size(), ext) == 0)
    return csv_path.substr(0, csv_path.size() - ext.size()) + ".truth.csv";
  return csv_path + ".truth.csv";
}

std::unique_ptr<CsvWriter> truth_writer(const std::string& truth_path, const TruthTable& tr,
                                        const std::vector<std::string>& comments) {
  std::vector<std::string> tcomments = comments;
  tcomments.push_back(
      "ground truth per tick; units: t tc s; cx cy cz ax ay az mm; tfx tfy tfz N; k N/mm (F/depth "
      "at 5 N); contact 0/1; tap = contact episode index or -1; nan = not in contact");
  auto tw = std::make_unique<CsvWriter>(
      truth_path,
      std::vector<std::string>{"t", "contact", "tap", "tc", "cx", "cy", "cz", "ax", "ay", "az",
                               "tfx", "tfy", "tfz", "k", "mu"},
      tcomments);
  std::vector<double> trow(15);
  for (std::size_t i = 0; i < tr.size(); ++i) {
    trow[0] = tr.t[i];
    trow[1] = tr.contact[i];
    trow[2] = static_cast<double>(tr.tap[i]);
    trow[3] = tr.tc[i];
    for (int k = 0; k < 3; ++k)
      trow[4 + k] = tr.c[i][k], trow[7 + k] = tr.anchor[i][k], trow[10 + k] = tr.force[i][k];
    trow[13] = tr.k[i];
    trow[14] = tr.mu[i];
    tw->row(trow);
  }
  return tw;
}

void write_lab_recording(const std::string& csv_path, const LabRecording& lab) {
  const Recording& rec = lab.rec;
  std::vector<std::string> comments = lab.comments;
  comments.push_back(
      "units: t s; px py pz mm (encoder, probe centre); fx fy fz N (compensated contact force "
      "on the probe); rfx rfy rfz N (raw force sensor, device frame)");
  std::vector<std::string> header = {"t", "px", "py", "pz", "fx", "fy", "fz"};
  header.insert(header.end(), rec.extra_names.begin(), rec.extra_names.end());
  CsvWriter w(csv_path, header, comments);
  std::vector<double> row(header.size());
  for (std::size_t i = 0; i < rec.size(); ++i) {
    row[0] = rec.t[i];
    for (int k = 0; k < 3; ++k) row[1 + k] = rec.p[i][k], row[4 + k] = rec.f[i][k];
    for (std::size_t e = 0; e < rec.extra.size(); ++e) row[7 + e] = rec.extra[e][i];
    w.row(row);
  }

  auto tw = truth_writer(truth_path_for(csv_path), lab.truth, lab.comments);
  w.commit();
  tw->commit();
}

TruthTable read_truth(const std::string& path) {
  static constexpr std::string_view kCols[] = {"t",   "contact", "tap", "tc", "cx",
                                               "cy",  "cz",      "ax",  "ay", "az",
                                               "tfx", "tfy",     "tfz", "k",  "mu"};
  const CsvTable tab = read_csv(path, kCols);
  TruthTable tr;
  const std::size_t n = tab.rows();
  auto col = [&](std::string_view name) -> const std::vector<double>& { return tab.column(name); };
  auto v3 = [&](const char* a, const char* b, const char* c, std::size_t i) {
    return Vec3(col(a)[i], col(b)[i], col(c)[i]);
  };
  for (std::size_t i = 0; i < n; ++i) {
    tr.t.push_back(col("t")[i]);
    tr.contact.push_back(static_cast<int>(col("contact")[i]));
    tr.tap.push_back(static_cast<long>(col("tap")[i]));
    tr.tc.push_back(col("tc")[i]);
    tr.c.push_back(v3("cx", "cy", "cz", i));
    tr.anchor.push_back(v3("ax", "ay", "az", i));
    tr.force.push_back(v3("tfx", "tfy", "tfz", i));
    tr.k.push_back(col("k")[i]);
    tr.mu.push_back(col("mu")[i]);
  }
  return tr;
}

}  // namespace inhap::lab
