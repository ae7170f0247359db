// inhap demo: TCA-MESH vs CBA stroke pairs and their figures, and the three.js mesh JSON shared
// by the 3-D figures. Units: mm, N, s, N/mm.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "inhap/geometry/trimesh.hpp"
#include "inhap/rendering/stroke.hpp"
#include "inhap/report/report.hpp"

namespace inhap::report {

struct StrokeCase {
  std::string name;
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();  ///< mm
  double force_n = 1.0;
  /// True surface height under (x, y), mm; empty when unknown (then the IHIP is the reference).
  std::function<double(double, double)> truth;
};

struct StrokePair {
  std::vector<rendering::StrokeSample> tca, cba;
  /// RMS of HIP height minus the reference over the sliding part, each stroke's mean removed, mm.
  double distortion_tca = 0, distortion_cba = 0;
};

struct StrokeLine {
  std::vector<rendering::StrokeSample> samples;
  std::string color;
};

/// Folder with the real data sets (afm-topography/, bunny/, headsq/): `given` (checked; Error
/// when a file is missing), else INHAP_DATA, else data/ beside or above the executable or in the
/// working directory; empty when none is found.
std::string find_data_dir(const std::string& given);

/// Heights (z, mm) of the HIP (which 0), IHIP (1) or CIHIP (2) along the sliding part of a
/// stroke from `from` in the unit direction `dir`, `len` mm long (in contact, 0.2 mm from either
/// end), at the distance along the stroke `u` (mm); thinned to about 600 points.
void sliding_heights(const std::vector<rendering::StrokeSample>& s, const Vec2& from,
                     const Vec2& dir, double len, int which, std::vector<double>& u,
                     std::vector<double>& z);

StrokePair run_stroke_pair(const rendering::Model& model, const StrokeCase& sc, std::uint64_t seed);
/// HIP / IHIP / CIHIP heights along the stroke for both algorithms (and the true surface).
Figure stroke_figure(const StrokeCase& sc, const StrokePair& p, const std::string& id,
                     const std::string& title);
void write_stroke_csv(const std::string& path, const StrokePair& p);
/// three.js mesh {positions, colors, indices} of `mesh` moved by `offset` (mm), vertex i
/// coloured by values[i] from lo (blue) through white to hi (red), clamped.
nlohmann::json colored_mesh_json(const TriMesh& mesh, const std::vector<double>& values, double lo,
                                 double hi, const Vec3& offset = Vec3::Zero());
/// three.js view of `mesh` coloured by `property` (height when empty or absent) with the HIP
/// paths of `lines`.
Figure mesh_figure(const TriMesh& mesh, const std::string& property,
                   const std::vector<StrokeLine>& lines, const std::string& id,
                   const std::string& title, const std::string& caption);

}  // namespace inhap::report
