// Recording -> proxy track, velocities, training set, replay (see dataset.hpp).
#include "inhap/datadriven/dataset.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "inhap/core/error.hpp"
#include "inhap/datadriven/servo.hpp"

namespace inhap::datadriven {

ProxyTrack proxy_from_columns(const Recording& rec, const std::string& path,
                              const std::string& prefix, const std::string& contact_column,
                              double force_threshold) {
  std::array<const std::vector<double>*, 3> qc{};
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    qc[static_cast<std::size_t>(a)] = rec.find_extra(prefix + axes[a]);
    if (!qc[static_cast<std::size_t>(a)])
      throw ParseError(
          path, 1,
          fmt::format(
              "expected proxy columns {0}x,{0}y,{0}z (from the proxy estimator), got no '{0}{1}'",
              prefix, axes[a]));
  }
  ProxyTrack t;
  t.proxy_source = "columns:" + prefix;
  const std::size_t n = rec.size();
  t.q.resize(n);
  t.contact.resize(n);
  const std::vector<double>* cc = contact_column.empty() ? nullptr : rec.find_extra(contact_column);
  t.contact_source = cc ? "column:" + contact_column : fmt::format("force>{}N", force_threshold);
  for (std::size_t i = 0; i < n; ++i) {
    t.q[i] = Vec3((*qc[0])[i], (*qc[1])[i], (*qc[2])[i]);
    t.contact[i] = cc ? ((*cc)[i] != 0.0) : (rec.f[i].norm() > force_threshold);
  }
  return t;
}

ProxyTrack position_only_track(const Recording& rec, const std::vector<char>& contact,
                               const std::string& contact_source) {
  if (contact.size() != rec.size())
    throw Error("position-only track: expected one contact flag per sample");
  ProxyTrack t;
  t.proxy_source = "none";
  t.contact_source = contact_source;
  t.contact = contact;
  t.q = rec.p;
  return t;
}

ProxyTrack entry_proxy_track(const Recording& rec, const std::vector<char>& contact,
                             const std::string& contact_source) {
  if (contact.size() != rec.size())
    throw Error("entry proxy: expected one contact flag per sample");
  ProxyTrack t;
  t.proxy_source = "entry";
  t.contact_source = contact_source;
  t.contact = contact;
  t.q.resize(rec.size());
  EntryProxyState s;
  for (std::size_t i = 0; i < rec.size(); ++i) t.q[i] = entry_proxy(s, rec.p[i], contact[i] != 0);
  return t;
}

std::vector<Vec3> foaw_velocities(const std::vector<Vec3>& p, const FoawParams& params) {
  params.validate();
  FoawState st;
  std::vector<Vec3> v(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) v[i] = foaw_step(params, st, p[i]);
  return v;
}

double median_dt(const Recording& rec) {
  if (rec.size() < 2) return 1e-3;
  std::vector<double> d(rec.size() - 1);
  for (std::size_t i = 1; i < rec.size(); ++i) d[i - 1] = rec.t[i] - rec.t[i - 1];
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

TrainingSet make_training_set(const Recording& rec, const ProxyTrack& proxy,
                              const FoawParams& foaw) {
  if (proxy.size() != rec.size() || proxy.contact.size() != rec.size())
    throw Error(fmt::format("training set: expected a proxy for each of the {} samples, got {}",
                            rec.size(), proxy.size()));
  const std::vector<Vec3> v = foaw_velocities(rec.p, foaw);
  TrainingSet s;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    if (!proxy.contact[i]) continue;
    const double moved = i > 0 && proxy.contact[i - 1] ? (proxy.q[i] - proxy.q[i - 1]).norm() : 0.0;
    const double dt = i > 0 && rec.t[i] > rec.t[i - 1] ? rec.t[i] - rec.t[i - 1] : foaw.dt_s;
    s.slip.push_back(moved > kSlidingStepMm ? moved / dt : 0.0);
    s.p.push_back(rec.p[i]);
    s.v.push_back(v[i]);
    s.q.push_back(proxy.q[i]);
    s.f.push_back(rec.f[i]);
    if (proxy.n.size() == rec.size()) s.n.push_back(proxy.n[i]);
  }
  return s;
}

std::vector<Vec3> replay(const ForceModel& model, const Recording& rec, const ProxyTrack& proxy,
                         std::vector<double>* step_us) {
  if (proxy.size() != rec.size() || proxy.contact.size() != rec.size())
    throw Error(fmt::format("replay: expected a proxy for each of the {} samples, got {}",
                            rec.size(), proxy.size()));
  ServoState st;
  // The model's velocity filter at this recording's rate (it may differ from the training's).
  const FoawParams foaw = model.foaw.at_period(median_dt(rec));
  std::vector<Vec3> out(rec.size());
  if (step_us) {
    step_us->clear();
    step_us->reserve(rec.size());
  }
  using Clock = std::chrono::steady_clock;
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const Clock::time_point t0 = step_us ? Clock::now() : Clock::time_point{};
    out[i] = servo_step(model, foaw, st, rec.p[i], proxy.q[i],
                        proxy.n.size() == rec.size() ? proxy.n[i] : Vec3::UnitZ(),
                        proxy.contact[i] != 0);
    if (step_us && proxy.contact[i])
      step_us->push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  return out;
}

}  // namespace inhap::datadriven
