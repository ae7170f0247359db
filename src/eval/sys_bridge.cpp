#include "inhap/eval/sys_bridge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <optional>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/friction/cycles_io.hpp"
#include "inhap/friction/mesh_surface.hpp"
#include "inhap/geometry/mesh_io.hpp"

namespace inhap::eval {

BridgePalpationResult palpate_bridge(const BridgePalpationOptions& o) {
  if (o.shape.empty() || o.refs.empty())
    throw Error("--device needs --shape MESH (probe-centre surface) and --refs REFS.csv");
  const friction::MeshSurface shape(read_mesh(o.shape), o.probe_radius_mm);
  std::vector<Vec3> points, normals;
  read_reference_points(o.refs, shape, points, normals);
  haptics::BridgeOptions bo;
  const std::optional<std::uint16_t> port = haptics::parse_udp_device(o.device);
  if (!port)
    throw Error(fmt::format("--device: expected udp or udp:PORT (PORT 1-65535), got {}",
                            quote_token(o.device)));
  bo.port = *port;
  bo.info.tool_mass_kg = o.tool_mass_kg;
  bo.info.probe_radius_mm = o.probe_radius_mm;
  haptics::BridgeDevice dev(bo);
  if (o.on_listening) o.on_listening(dev.port());
  if (!dev.connect(o.connect_s))
    throw Error(fmt::format("no device joined within {:g} s", o.connect_s));
  const friction::PalpationConfig cfg = palpation_config(o.quick);
  const DevicePalpation r = palpate_points(dev, shape, points, normals, cfg, o.progress, o.label);
  dev.stop();
  BridgePalpationResult out;
  out.sys = fit_palpation(r.cycles, shape, cfg);
  out.cycles = r.cycles;
  out.ticks = r.ticks;
  out.bridge = dev.stats();
  return out;
}

Vec3 parse_vec3(const std::string& s, const std::string& what) {
  Vec3 v;
  if (std::sscanf(s.c_str(), "%lf,%lf,%lf", &v.x(), &v.y(), &v.z()) != 3 || !v.allFinite())
    throw Error(fmt::format("{}: expected x,y,z, got '{}'", what, s));
  return v;
}

std::string sys_output_stem(const std::string& out) {
  return out.size() > 5 && out.substr(out.size() - 5) == ".json" ? out.substr(0, out.size() - 5)
                                                                 : out;
}

std::string beyond_rim_warning(const ProxyFileResult& r, const std::string& mesh_path) {
  if (r.beyond == 0) return {};
  return fmt::format(
      "inhap: warning: {} of {} in-contact samples ({:.1f} %) lie beyond the rim of the "
      "shape mesh {} (up to {:.2f} mm; column beyond_mesh): the proxy there follows the "
      "rim, not the object; model a wider area of the object\n",
      r.beyond, r.contact, 100.0 * double(r.beyond) / double(std::max<std::size_t>(r.contact, 1)),
      mesh_path, r.beyond_max_mm);
}

void write_scene_palpation(const std::string& out, const ScenePalpation& r) {
  const std::string stem = sys_output_stem(out);
  OutputTransaction tx;  // four outputs: all or none
  friction::write_cycles_csv(stem + ".cycles.csv", r.cycles);
  write_mesh(stem + ".shape.ply", r.shape_mesh);
  write_reference_points(stem + ".refs.csv", r.points, r.normals);
  friction::write_sys_json(out, r.sys);
  tx.commit();
}

std::string scene_palpation_text(const std::string& out, const ScenePalpation& r) {
  const std::string stem = sys_output_stem(out);
  return fmt::format(
             "{} cycles, {:.2f} simulated hours, {:.1f} s wall ({:.1f} s per point, {:.1f} s "
             "CPU)\n",
             r.cycles.size(), r.ticks / 3.6e6, r.wall_s, r.wall_s / r.points.size(), r.cpu_s) +
         fmt::format("wrote {}, {}.cycles.csv, {}.shape.ply, {}.refs.csv\n", out, stem, stem, stem);
}

ProxyFileRun proxy_file(const std::string& sys_path, const std::string& mesh_path,
                        const std::string& recording, const std::string& out,
                        double probe_radius_mm, bool creep) {
  const friction::SysModel sys = friction::read_sys_json(sys_path);
  const TriMesh mesh = read_mesh(mesh_path);
  Recording rec = read_recording(recording);
  ProxyFileRun r;
  r.counts = add_proxy_columns(rec, sys, mesh, probe_radius_mm, creep);
  write_recording(out, rec);
  r.rows = rec.size();
  return r;
}

}  // namespace inhap::eval
