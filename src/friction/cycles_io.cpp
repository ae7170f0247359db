#include "inhap/friction/cycles_io.hpp"

#include <fmt/format.h>

#include <cmath>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"

namespace inhap::friction {

namespace {

const std::vector<std::string> kColumns = {
    "point", "cx",  "cy",  "cz",  "fn",  "ft",  "t_plateau", "dir",     "angle", "tx",
    "ty",    "tz",  "pcx", "pcy", "pcz", "ncx", "ncy",       "ncz",     "fmx",   "fmy",
    "fmz",   "umx", "umy", "umz", "prx", "pry", "prz",       "t_start", "status"};

constexpr double kMaxMagnitude = 1e6;

}  // namespace

void write_cycles_csv(const std::string& path, std::span<const CycleRecord> cycles) {
  const std::vector<std::string> comments = {
      "inhap palpation cycles (thesis 4.3.2): one loading-unloading cycle per row",
      "units: positions/displacements mm, forces N, times s, angles rad; u^p = p_r - p_c"};
  CsvWriter w(path, kColumns, comments);
  for (const CycleRecord& c : cycles) {
    w.row({static_cast<double>(c.point),
           c.reference.x(),
           c.reference.y(),
           c.reference.z(),
           c.f_normal,
           c.f_tangential,
           c.t_plateau,
           static_cast<double>(c.direction),
           c.angle,
           c.tdir.x(),
           c.tdir.y(),
           c.tdir.z(),
           c.pc.x(),
           c.pc.y(),
           c.pc.z(),
           c.nc.x(),
           c.nc.y(),
           c.nc.z(),
           c.f_meas.x(),
           c.f_meas.y(),
           c.f_meas.z(),
           c.u_meas.x(),
           c.u_meas.y(),
           c.u_meas.z(),
           c.pr.x(),
           c.pr.y(),
           c.pr.z(),
           c.t_start,
           static_cast<double>(static_cast<int>(c.status))});
  }
  w.commit();
}

std::vector<CycleRecord> read_cycles_csv(const std::string& path) {
  CsvReader r(path);
  auto req = [&](const char* name) { return r.require(name); };
  auto opt = [&](const char* name) { return r.find(name); };
  const std::size_t i_point = req("point"), i_fn = req("fn"), i_ft = req("ft"),
                    i_tp = req("t_plateau"), i_dir = req("dir");
  const std::size_t i_t[3] = {req("tx"), req("ty"), req("tz")};
  const std::size_t i_pc[3] = {req("pcx"), req("pcy"), req("pcz")};
  const std::size_t i_nc[3] = {req("ncx"), req("ncy"), req("ncz")};
  const std::size_t i_fm[3] = {req("fmx"), req("fmy"), req("fmz")};
  const std::size_t i_um[3] = {req("umx"), req("umy"), req("umz")};
  const std::size_t i_pr[3] = {req("prx"), req("pry"), req("prz")};
  const auto i_cx = opt("cx"), i_cy = opt("cy"), i_cz = opt("cz");
  const auto i_angle = opt("angle"), i_ts = opt("t_start"), i_status = opt("status");

  std::vector<CycleRecord> out;
  while (r.next()) {
    // Positions (mm), forces (N) and times (s) beyond 1e6 are absurd, and squaring 1e308
    // overflows: the fit would write `null` into sys.json.
    for (double v : r.values())
      if (!std::isfinite(v) || std::abs(v) > kMaxMagnitude)
        throw ParseError(
            path, r.line(),
            fmt::format("expected finite numbers within +-{:g} in every column, got {}",
                        kMaxMagnitude, v));
    auto integer = [&](std::size_t col, const char* name, int lo, int hi) {
      const double v = r[col];
      if (v != std::floor(v) || v < lo || v > hi)
        throw ParseError(
            path, r.line(),
            fmt::format("expected an integer {} in [{}, {}], got {}", name, lo, hi, v));
      return static_cast<int>(v);
    };
    auto vec = [&](const std::size_t(&cols)[3]) {
      return Vec3(r[cols[0]], r[cols[1]], r[cols[2]]);
    };
    CycleRecord c;
    c.point = integer(i_point, "point", 0, 1 << 20);
    c.direction = integer(i_dir, "dir", 0, 63);
    c.f_normal = r[i_fn];
    c.f_tangential = r[i_ft];
    c.t_plateau = r[i_tp];
    if (c.f_normal <= 0 || c.f_tangential < 0 || c.t_plateau < 0)
      throw ParseError(path, r.line(), "expected fn > 0 N, ft >= 0 N and t_plateau >= 0 s");
    c.tdir = vec(i_t);
    c.nc = vec(i_nc);
    if (std::abs(c.tdir.norm() - 1.0) > 0.05 || std::abs(c.nc.norm() - 1.0) > 0.05)
      throw ParseError(path, r.line(), "expected unit vectors in tx,ty,tz and ncx,ncy,ncz");
    c.tdir.normalize();
    c.nc.normalize();
    c.pc = vec(i_pc);
    c.f_meas = vec(i_fm);
    c.u_meas = vec(i_um);
    c.pr = vec(i_pr);
    c.reference = (i_cx && i_cy && i_cz) ? Vec3(r[*i_cx], r[*i_cy], r[*i_cz]) : c.pc;
    c.angle = i_angle ? r[*i_angle] : 0.0;
    c.t_start = i_ts ? r[*i_ts] : 0.0;
    c.status =
        i_status ? static_cast<CycleStatus>(integer(*i_status, "status", 0, 5)) : CycleStatus::ok;
    out.push_back(c);
  }
  if (out.empty()) throw ParseError(path, r.header_line(), "expected at least one cycle row");
  return out;
}

}  // namespace inhap::friction
