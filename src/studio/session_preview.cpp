// inhap studio session: the sampling view's outlier filter and jet (quadric) projection,
// previewed before a reconstruction and applied on confirm (session.hpp). The same library
// functions and settings as the first two steps of reconstruct_surface (ReconstructOptions'
// defaults): k-NN outlier removal, then a second-order jet fitted to each kept sample's
// neighbours with directions within jet_max_angle_deg, the sample moved onto it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "inhap/studio/session.hpp"
#include "inhap/surface/points.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace inhap::studio {

Session::Preview Session::compute_preview() const {
  std::vector<long> ids;
  std::vector<Vec3> pts, dirs;
  {
    std::lock_guard lock(data_mu_);
    for (const Sample& s : samples_)
      if (!s.deleted) ids.push_back(s.id), pts.push_back(s.point), dirs.push_back(s.direction);
  }
  const ReconstructOptions o;
  if (pts.size() < std::max<std::size_t>(o.outlier_k + 2, 8))
    throw ProtocolError(fmt::format("preview: {} samples, expected at least {}", pts.size(),
                                    std::max<std::size_t>(o.outlier_k + 2, 8)));
  const std::vector<std::size_t> kept = remove_knn_outliers(pts, o.outlier_k, o.outlier_sigmas);
  Preview p;
  std::vector<Vec3> kp, kd;
  std::vector<long> kid;
  for (std::size_t i = 0, j = 0; i < pts.size(); ++i) {
    if (j < kept.size() && kept[j] == i) {
      kp.push_back(pts[i]), kd.push_back(dirs[i]), kid.push_back(ids[i]);
      ++j;
    } else {
      p.outliers.push_back(ids[i]);
    }
  }
  const double cos_max = std::cos(o.jet_max_angle_deg * 3.14159265358979323846 / 180.0);
  const std::vector<Vec3> moved = jet_smooth(kp, o.jet_k, kd, cos_max, o.jet_feature_factor);
  for (std::size_t i = 0; i < moved.size(); ++i) p.moves.emplace_back(kid[i], moved[i]);
  return p;
}

std::string Session::do_preview() {
  const Preview p = compute_preview();
  nlohmann::json moves = nlohmann::json::array();
  std::vector<double> d;
  {
    std::lock_guard lock(data_mu_);
    for (const auto& [id, to] : p.moves) {
      const auto it = std::find_if(samples_.begin(), samples_.end(),
                                   [id](const Sample& s) { return s.id == id; });
      d.push_back((to - it->point).norm());
      moves.push_back({{"id", id}, {"to", {to.x(), to.y(), to.z()}}, {"d", d.back()}});
    }
  }
  std::vector<double> sorted = d;
  std::sort(sorted.begin(), sorted.end());
  return nlohmann::json{{"type", "preview"},
                        {"outliers", p.outliers},
                        {"moves", moves},
                        {"median_move", sorted.empty() ? 0.0 : sorted[sorted.size() / 2]},
                        {"max_move", sorted.empty() ? 0.0 : sorted.back()}}
      .dump();
}

// Deletes the outliers and moves the rest onto their jets, as one step that undo reverts. The
// preview is computed again here (the samples may have changed since the page asked).
std::string Session::do_apply_preview() {
  const Preview p = compute_preview();
  {
    std::lock_guard lock(data_mu_);
    UndoStep step;
    for (Sample& s : samples_) {
      if (s.deleted) continue;
      if (std::find(p.outliers.begin(), p.outliers.end(), s.id) != p.outliers.end()) {
        s.deleted = true;
        step.deleted.push_back(s.id);
        continue;
      }
      const auto it = std::find_if(p.moves.begin(), p.moves.end(),
                                   [&s](const auto& m) { return m.first == s.id; });
      if (it == p.moves.end()) continue;
      step.moved.emplace_back(s.id, s.point);
      s.point = it->second;
    }
    undo_.push_back(std::move(step));
  }
  return samples_json();
}

}  // namespace inhap::studio
