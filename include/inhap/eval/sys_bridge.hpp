// `inhap sys palpate --device udp[:PORT]`: the palpation protocol (thesis 4.3.2) on a device that
// joins over the UDP bridge (a real one, or `inhap lab device --operator none`), on a shape mesh
// and reference points the user gives; plus the small helpers of the `sys` commands.
// Units: mm, N, s.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "inhap/core/types.hpp"
#include "inhap/eval/progress.hpp"
#include "inhap/eval/sys_files.hpp"
#include "inhap/friction/palpation.hpp"
#include "inhap/friction/sys_model.hpp"
#include "inhap/haptics/bridge_device.hpp"

namespace inhap::eval {

struct BridgePalpationOptions {
  std::string device;  ///< udp or udp:PORT
  std::string shape;   ///< shape mesh (probe-centre surface, or the object's with radius)
  std::string refs;    ///< reference points CSV x,y,z[,nx,ny,nz], mm
  double probe_radius_mm = 0, tool_mass_kg = 0;
  double connect_s = 60;  ///< give up when no device joins within this, s
  bool quick = false;     ///< palpation_config(quick)
  Progress progress;      ///< per point, labelled `label`
  std::string label = "sys palpate";
  /// Called with the port once the bridge listens (before waiting for the device).
  std::function<void(std::uint16_t port)> on_listening;
};

struct BridgePalpationResult {
  std::vector<friction::CycleRecord> cycles;
  friction::SysModel sys;
  long ticks = 0;  ///< protocol ticks (1 ms)
  haptics::BridgeStats bridge;
};

/// Opens the bridge, waits for a device, palpates every reference point and fits the sliding
/// yield surfaces. Throws inhap::Error (naming the flag: --device, --shape, --refs) on bad
/// options, when no device joins in time or a point fails.
BridgePalpationResult palpate_bridge(const BridgePalpationOptions& o);

/// `sys palpate`'s four outputs of a lab palpation, all or none: <stem>.cycles.csv,
/// <stem>.shape.ply, <stem>.refs.csv and the sys.json `out`.
void write_scene_palpation(const std::string& out, const ScenePalpation& r);
/// Its summary on stderr: cycles, simulated hours, wall and CPU time, the files written.
std::string scene_palpation_text(const std::string& out, const ScenePalpation& r);

/// "x,y,z" as a vector; throws inhap::Error "`what`: expected x,y,z, got '...'" otherwise.
Vec3 parse_vec3(const std::string& s, const std::string& what);

/// The stem of the sidecar files of a sys.json output: the path without ".json".
std::string sys_output_stem(const std::string& out);

/// `sys proxy` on files: reads the sliding yield surfaces, the shape mesh and the recording, adds
/// the proxy columns (add_proxy_columns) and writes the recording to `out`; returns the counts
/// and the rows written.
struct ProxyFileRun {
  ProxyFileResult counts;
  std::size_t rows = 0;
};
ProxyFileRun proxy_file(const std::string& sys, const std::string& mesh,
                        const std::string& recording, const std::string& out,
                        double probe_radius_mm, bool creep);

/// The warning of `sys proxy` when in-contact samples lie beyond the rim of the shape mesh
/// (empty when none do).
std::string beyond_rim_warning(const ProxyFileResult& r, const std::string& mesh_path);

}  // namespace inhap::eval
