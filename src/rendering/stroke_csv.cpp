// A simulated stroke as a CSV file and in one line. Units: mm, N, N/mm, s.
#include "inhap/rendering/stroke_csv.hpp"

#include <fmt/format.h>

#include "inhap/core/csv.hpp"

namespace inhap::rendering {

void write_stroke_csv(const std::string& path, const std::vector<StrokeSample>& samples,
                      const std::string& command) {
  const std::vector<std::string> comments = {
      command,
      "units: t s; px,py,pz HIP mm; qx,qy,qz IHIP mm; cx,cy,cz CIHIP mm; fx,fy,fz force on the "
      "probe N; k N/mm; s mm; tx,ty,tz mesh compensation t mm; contact 0/1"};
  CsvWriter csv(path,
                {"t", "px", "py", "pz", "qx", "qy", "qz", "cx", "cy", "cz", "fx", "fy", "fz", "k",
                 "s", "tx", "ty", "tz", "contact"},
                comments);
  for (const auto& e : samples)
    csv.row({e.time, e.hip.x(), e.hip.y(), e.hip.z(), e.ihip.x(), e.ihip.y(), e.ihip.z(),
             e.cihip.x(), e.cihip.y(), e.cihip.z(), e.force.x(), e.force.y(), e.force.z(), e.k, e.s,
             e.t.x(), e.t.y(), e.t.z(), e.contact ? 1.0 : 0.0});
  csv.commit();
}

std::string stroke_summary(const std::vector<StrokeSample>& samples) {
  std::size_t contact = 0;
  double fsum = 0;
  for (const auto& e : samples) {
    contact += e.contact;
    fsum += e.contact ? e.force.norm() : 0.0;
  }
  return fmt::format("{} ticks ({:.3f} s), {} in contact, mean contact force {:.3f} N",
                     samples.size(), samples.empty() ? 0.0 : samples.back().time, contact,
                     contact ? fsum / double(contact) : 0.0);
}

}  // namespace inhap::rendering
