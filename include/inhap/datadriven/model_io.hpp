// Force-model files: versioned JSON ("format": "inhap-force-model", "version": 1).
//
// Units in the file: mm, mm/s, N, s (stated in its "units" object). Doubles are written in the
// shortest form that reads back to the same bits, so forces are bit-identical after
// save -> load. A 5-bin, 300-centre model is about 1 MB; no binary sidecar is needed at that
// size. The file holds the bins (||q - p|| edges), the per-bin normalisation and clamping box,
// the centres (normalised) and weights of every axis, the FOAW parameters, the references to
// the sliding-yield-surface (SYS) file and shape mesh (path + FNV-1a 64 digest), the training
// parameters and statistics. Loading validates everything and throws inhap::ParseError naming
// the file, the line (for syntax errors) and the JSON path of the offending value.
#pragma once

#include <string>

#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {

inline constexpr int kForceModelVersion = 1;

/// Writes atomically. Throws IoError.
void save_force_model(const std::string& path, const ForceModel& model);
/// Reads and validates. Throws ParseError / IoError.
ForceModel load_force_model(const std::string& path);

/// Model <-> JSON text (what save/load use).
std::string force_model_to_json(const ForceModel& model);
ForceModel force_model_from_json(const std::string& text, const std::string& source_name);

/// FNV-1a 64-bit digest of a file's bytes as 16 hex digits. Throws IoError.
std::string file_digest(const std::string& path);

}  // namespace inhap::datadriven
