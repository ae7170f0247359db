// Contact points to PLY / CSV; see contact_io.hpp.
#include "inhap/contact/contact_io.hpp"

#include <string>
#include <vector>

#include "inhap/core/csv.hpp"
#include "inhap/geometry/ply.hpp"

namespace inhap {

TriMesh contacts_to_points(std::span<const Contact> contacts) {
  TriMesh m;
  std::vector<double> tap, tc, td, peak, est;
  for (const Contact& c : contacts) {
    m.positions.push_back(c.point);
    m.normals.push_back(c.direction);
    tap.push_back(static_cast<double>(c.tap));
    tc.push_back(c.t_contact);
    td.push_back(c.t_detect);
    peak.push_back(c.peak_force);
    est.push_back(c.estimated ? 1.0 : 0.0);
  }
  m.set_property("tap", std::move(tap));
  m.set_property("t_contact", std::move(tc));
  m.set_property("t_detect", std::move(td));
  m.set_property("peak_force", std::move(peak));
  m.set_property("estimated", std::move(est));
  return m;
}

void write_contact_points(const std::string& path, std::span<const Contact> contacts, bool ascii) {
  PlyWriteOptions o;
  o.format = ascii ? PlyFormat::kAscii : PlyFormat::kBinaryLittleEndian;
  write_ply(path, contacts_to_points(contacts), o);
}

void write_contact_table(const std::string& path, std::span<const Contact> contacts) {
  const std::vector<std::string> comments = {
      "contact points; units: t s, positions mm, peak_force N; estimated 1 = knee fit, 0 = "
      "threshold"};
  CsvWriter w(path,
              {"tap", "t_detect", "t_contact", "x", "y", "z", "dx", "dy", "dz", "xd", "yd", "zd",
               "peak_force", "estimated"},
              comments);
  for (const Contact& c : contacts)
    w.row({static_cast<double>(c.tap), c.t_detect, c.t_contact, c.point.x(), c.point.y(),
           c.point.z(), c.direction.x(), c.direction.y(), c.direction.z(), c.p_detect.x(),
           c.p_detect.y(), c.p_detect.z(), c.peak_force, c.estimated ? 1.0 : 0.0});
  w.commit();
}

}  // namespace inhap
