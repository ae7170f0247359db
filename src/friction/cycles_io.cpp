#include "inhap/friction/cycles_io.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <optional>

#include "inhap/core/csv.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/surface_frame.hpp"

namespace inhap::friction {

namespace {

const std::vector<std::string> kColumns = {
    "point", "cx",  "cy",  "cz",  "fn",  "ft",  "t_plateau", "dir",     "angle",  "tx",
    "ty",    "tz",  "pcx", "pcy", "pcz", "ncx", "ncy",       "ncz",     "fmx",    "fmy",
    "fmz",   "umx", "umy", "umz", "prx", "pry", "prz",       "t_start", "status", "t_measurement"};

constexpr double kMaxMagnitude = 1e6;
// A measurement taken on the servo tick after the plateau's end is still "in the plateau".
constexpr double kMeasurementSlack_s = 2e-3;

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
           static_cast<double>(static_cast<int>(c.status)),
           c.t_measurement_s});
  }
  w.commit();
}

namespace {

using Cols = std::optional<std::array<std::size_t, 3>>;

/// x,y,z columns `<stem>x`,`<stem>y`,`<stem>z`: all three or none (a partial set is an error).
Cols vec_columns(const CsvReader& r, const std::string& stem) {
  const auto x = r.find(stem + "x"), y = r.find(stem + "y"), z = r.find(stem + "z");
  if (!x && !y && !z) return std::nullopt;
  if (!x || !y || !z)
    throw ParseError(r.path(), r.header_line(),
                     fmt::format("expected all of {0}x,{0}y,{0}z or none of them", stem));
  return std::array<std::size_t, 3>{*x, *y, *z};
}

Vec3 vec_at(const CsvReader& r, const std::array<std::size_t, 3>& c) {
  return Vec3(r[c[0]], r[c[1]], r[c[2]]);
}

/// n_c and t_k of the current row: from the columns, else from the shape and the angle.
void frame_of_row(const CsvReader& r, const Cols& t_cols, const Cols& n_cols,
                  std::optional<std::size_t> i_angle, const CycleGeometry& g, CycleRecord& c) {
  if (n_cols) {
    c.nc = vec_at(r, *n_cols);
  } else {
    Vec3 point;
    if (!g.shape->closest(c.pc, point, c.nc, g.max_distance_mm) || !c.nc.allFinite())
      throw ParseError(r.path(), r.line(),
                       fmt::format("expected p_c within {:g} mm of the shape mesh to take the "
                                   "normal from (no ncx,ncy,ncz columns)",
                                   g.max_distance_mm));
  }
  if (t_cols) {
    c.tdir = vec_at(r, *t_cols);
  } else {
    Vec3 t0, t1;
    tangent_basis(c.nc.normalized(), g.tangent_reference, t0, t1);
    c.tdir = std::cos(r[*i_angle]) * t0 + std::sin(r[*i_angle]) * t1;
  }
  if (std::abs(c.tdir.norm() - 1.0) > 0.05 || std::abs(c.nc.norm() - 1.0) > 0.05)
    throw ParseError(r.path(), r.line(), "expected unit vectors in tx,ty,tz and ncx,ncy,ncz");
  c.tdir.normalize();
  c.nc.normalize();
}

}  // namespace

std::vector<CycleRecord> read_cycles_csv(const std::string& path, const CycleGeometry& geometry) {
  CsvReader r(path);
  auto req = [&](const char* name) { return r.require(name); };
  auto opt = [&](const char* name) { return r.find(name); };
  const std::size_t i_point = req("point"), i_fn = req("fn"), i_ft = req("ft"),
                    i_tp = req("t_plateau"), i_dir = req("dir");
  const Cols t_cols = vec_columns(r, "t"), n_cols = vec_columns(r, "nc");
  const auto i_angle = opt("angle");
  if (!n_cols && !geometry.shape)
    throw ParseError(path, r.header_line(),
                     "expected columns ncx,ncy,ncz (or a shape mesh to take the normal from: "
                     "sys fit --mesh)");
  if (!t_cols && !i_angle)
    throw ParseError(path, r.header_line(),
                     "expected columns tx,ty,tz, or angle to derive the direction from");
  const std::size_t i_pc[3] = {req("pcx"), req("pcy"), req("pcz")};
  const std::size_t i_fm[3] = {req("fmx"), req("fmy"), req("fmz")};
  const std::size_t i_um[3] = {req("umx"), req("umy"), req("umz")};
  const std::size_t i_pr[3] = {req("prx"), req("pry"), req("prz")};
  const auto i_cx = opt("cx"), i_cy = opt("cy"), i_cz = opt("cz");
  const auto i_ts = opt("t_start"), i_status = opt("status"), i_tm = opt("t_measurement");

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
    c.pc = vec(i_pc);
    frame_of_row(r, t_cols, n_cols, i_angle, geometry, c);
    c.f_meas = vec(i_fm);
    c.u_meas = vec(i_um);
    c.pr = vec(i_pr);
    c.reference = (i_cx && i_cy && i_cz) ? Vec3(r[*i_cx], r[*i_cy], r[*i_cz]) : c.pc;
    c.angle = i_angle ? r[*i_angle] : 0.0;
    c.t_start = i_ts ? r[*i_ts] : 0.0;
    if (i_tm) c.t_measurement_s = r[*i_tm];
    if (c.t_measurement_s > c.t_plateau + kMeasurementSlack_s)
      throw ParseError(path, r.line(),
                       fmt::format("expected t_measurement <= t_plateau ({} s; seconds after the "
                                   "plateau start), got {}",
                                   c.t_plateau, c.t_measurement_s));
    c.status =
        i_status ? static_cast<CycleStatus>(integer(*i_status, "status", 0, 5)) : CycleStatus::kOk;
    out.push_back(c);
  }
  if (out.empty()) throw ParseError(path, r.header_line(), "expected at least one cycle row");
  return out;
}

}  // namespace inhap::friction
