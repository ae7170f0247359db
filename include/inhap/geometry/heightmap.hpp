// Height maps and stiffness maps on a regular grid, and their conversion to a triangle mesh.
// Units: heights in mm, pixel spacing in mm, stiffness in N/mm.
#pragma once

#include <string>
#include <vector>

#include "inhap/geometry/trimesh.hpp"

namespace inhap {

/// A W x H grid of values, row-major: value(x, y) = values[y * width + x].
struct Grid {
  int width = 0, height = 0;
  std::vector<double> values;

  Grid() = default;
  Grid(int w, int h, double fill = 0.0) : width(w), height(h), values(std::size_t(w) * h, fill) {}
  double& at(int x, int y) { return values[std::size_t(y) * width + x]; }
  double at(int x, int y) const { return values[std::size_t(y) * width + x]; }
  double min() const;
  double max() const;
};

/// Reads a grid: a CSV of numbers without header (one grid row per line), or a PGM image
/// (P2 ASCII or P5 binary, 8- or 16-bit; values are the raw pixel levels 0..maxval).
/// Throws ParseError naming file and line.
Grid read_grid(const std::string& path);

/// Reads a WSxM `.top` topography file: the text header (its size is given in the
/// "Image header size:" line) then int16 little-endian samples, rows x columns as given in the
/// header. Returns heights in the file's units scaled by its "Z Amplitude"-style conversion when
/// present, else raw levels (documented in docs/formats.md). Throws ParseError.
Grid read_wsxm_top(const std::string& path);

/// Removes the best-fitting plane z = a x + b y + c (least squares), "levelling the tilt".
void level_plane(Grid& grid);

/// Bilinear resampling to n x n samples spanning the whole grid (corner samples kept). The grid
/// needs at least 2 x 2 samples and n >= 2.
Grid resample_bilinear(const Grid& grid, int n);

/// Block average: each output pixel is the mean of a factor x factor block of input pixels,
/// output size floor(W / factor) x floor(H / factor) (a partial last row or column of blocks is
/// dropped). Use pixel spacing x factor for the result; its pixel (x, y) is the centre of input
/// block (x f + (f - 1) / 2, y f + (f - 1) / 2). Factor 1 returns a copy. Throws Error when the
/// factor is below 1 or leaves fewer than 2 x 2 pixels.
Grid downsample(const Grid& grid, int factor);

/// Grid -> mesh: vertex (x * spacing, y * spacing, height(x, y)); two triangles per cell,
/// 2 (W-1)(H-1) in all, counter-clockwise seen from +z (normals point up). With a stiffness
/// grid (same size, N/mm) the mesh gets a `stiffness` vertex property. Vertex normals computed.
TriMesh grid_to_mesh(const Grid& height, double spacing_mm, const Grid* stiffness = nullptr);

}  // namespace inhap
