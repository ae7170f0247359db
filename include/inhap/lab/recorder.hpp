// Virtual lab: recordings with ground truth beside them.
// Units: t s, positions mm, forces N, k N/mm.
//
// The recording (rec.csv) holds exactly what a real rig's logger running inhap writes:
//   t, px,py,pz  encoder position of the probe centre (0.01 mm steps),
//   fx,fy,fz     the raw reading compensated causally (inhap::compensate_step with the
//                device's exported DeviceInfo and the encoder stream),
//   rfx,rfy,rfz  the raw force-sensor reading (contact + noise + tool weight + tool inertia).
// The truth sidecar (rec.truth.csv), one row per tick:
//   t; contact (0/1); tap (index of the contact episode in this recording, from 0; -1 out of
//   contact); tc (true first-contact instant of that episode, interpolated between physics
//   substeps); cx,cy,cz (probe centre at tc: the thesis' contact point p(t_c)); ax,ay,az (true
//   tangential anchor = proxy q of thesis eq. 4.4); tfx,tfy,tfz (noise-free contact force);
//   k (effective normal stiffness at the anchor, F/depth at F = 5 N, N/mm); mu (friction at
//   the anchor). Out of contact tc, c, a, k, mu are NaN ("nan") and tf is 0.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "inhap/contact/compensation.hpp"
#include "inhap/core/csv.hpp"
#include "inhap/lab/sim_device.hpp"

namespace inhap::lab {

struct TruthTable {
  std::vector<double> t;
  std::vector<int> contact;
  std::vector<long> tap;
  std::vector<double> tc;
  std::vector<Vec3> c;       ///< first-contact point of the episode, mm
  std::vector<Vec3> anchor;  ///< proxy q, mm
  std::vector<Vec3> force;   ///< noise-free contact force on the probe, N
  std::vector<double> k;     ///< N/mm (F/depth at 5 N)
  std::vector<double> mu;
  std::size_t size() const { return t.size(); }
};

struct LabRecording {
  Recording rec;  ///< t, p, f (compensated) + extra rfx, rfy, rfz
  TruthTable truth;
  std::vector<std::string> comments;  ///< provenance, written as '#' lines
};

/// Samples a SimDevice once per tick into a LabRecording (call sample() before each tick).
class TickLogger {
 public:
  explicit TickLogger(const SimDevice& device, std::size_t reserve_ticks = 0);
  void sample();
  LabRecording take();
  std::size_t size() const { return out_.rec.size(); }

 private:
  const SimDevice& dev_;
  CompensatorConfig comp_cfg_;
  CompensatorState comp_;
  LabRecording out_;
  std::vector<double> rfx_, rfy_, rfz_;
  std::int64_t last_episode_ = -1;
  long taps_ = 0;
};

/// "rec.csv" -> "rec.truth.csv" (other names get ".truth.csv" appended).
std::string truth_path_for(const std::string& csv_path);
/// A truth sidecar's rows in a writer, not yet committed (commit() renames it into place).
std::unique_ptr<CsvWriter> truth_writer(const std::string& truth_path, const TruthTable& truth,
                                        const std::vector<std::string>& comments);
/// Writes the recording and its truth sidecar atomically.
void write_lab_recording(const std::string& csv_path, const LabRecording& lab);
/// Reads a truth sidecar back (NaN fields allowed).
TruthTable read_truth(const std::string& path);

}  // namespace inhap::lab
