// Force-model files: versioned JSON ("format": "inhap-force-model", "version": 1).
//
// Units in the file: mm, mm/s, N, s (stated in its "units" object). Doubles are written in the
// shortest form that reads back to the same bits, so forces are bit-identical after
// save -> load. A 5-bin, 300-centre model is about 1 MB; no binary sidecar is needed at that
// size. The file holds the bins (||q - p|| edges), the per-bin normalisation and clamping box,
// the centres (normalised) and weights of every axis, the FOAW parameters, the references to
// the sliding-yield-surface (SYS) file and shape mesh (path + FNV-1a 64 digest), the training
// parameters and statistics; the last three are the model's provenance (ForceModelProvenance),
// read and written beside the run-time model. Loading validates everything and throws
// inhap::ParseError naming the file, the line (for syntax errors) and the JSON path of the
// offending value.
#pragma once

#include <string>

#include "inhap/datadriven/force_model.hpp"

namespace inhap::datadriven {

inline constexpr int kForceModelVersion = 1;

/// Writes the model and its provenance (training parameters and statistics, references; a
/// default provenance when none is given) atomically. Throws IoError.
void save_force_model(const std::string& path, const ForceModel& model,
                      const ForceModelProvenance& provenance = {});
inline void save_force_model(const std::string& path, const TrainedForceModel& m) {
  save_force_model(path, m.model, m.provenance);
}
/// Reads and validates the model and its provenance. Throws ParseError / IoError.
TrainedForceModel load_trained_force_model(const std::string& path);
/// The same, the model alone.
ForceModel load_force_model(const std::string& path);

/// Model <-> JSON text (what save/load use).
std::string force_model_to_json(const ForceModel& model,
                                const ForceModelProvenance& provenance = {});
inline std::string force_model_to_json(const TrainedForceModel& m) {
  return force_model_to_json(m.model, m.provenance);
}
TrainedForceModel trained_force_model_from_json(const std::string& text,
                                                const std::string& source_name);
ForceModel force_model_from_json(const std::string& text, const std::string& source_name);

/// FNV-1a 64-bit digest of a file's bytes as 16 hex digits. Throws IoError.
std::string file_digest(const std::string& path);

}  // namespace inhap::datadriven
