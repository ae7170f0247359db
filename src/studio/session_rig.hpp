// inhap studio: what one view of a Session runs (private to src/studio). Units: mm, N, s.
#pragma once

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>

#include "inhap/studio/model_view.hpp"
#include "inhap/studio/session.hpp"

namespace inhap::studio {

// What one view runs: the device (lab) or the shared bridge, the renderer and its model, the
// loop and its observer ring.
struct Session::Rig {
  std::unique_ptr<LabHandDevice> lab_device;
  std::unique_ptr<RecordingDevice> rec_device;  ///< the Model view's recording
  std::shared_ptr<DataDrivenBundle> bundle;     ///< the trained model the compare renderer reads
  Device* device = nullptr;
  TargetMailbox mailbox;
  MouseOperator* mouse = nullptr;
  PalpationRenderer* palp = nullptr;  ///< the palpation protocol, while it runs
  std::unique_ptr<rendering::Model> model;
  std::unique_ptr<haptics::Renderer> renderer;
  haptics::ObserverRing ring;
  std::unique_ptr<haptics::ServoLoop> loop;
  CompensatorConfig comp;
  CompensatorState comp_state;
  StreamTapDetector taps;
  // the Model view
  RecordingDevice* recorder = nullptr;  ///< recording (the device)
  bool observed = false;  ///< recording a bridged device from the ring (ModelStream::observed)
  CompareRenderer* compare = nullptr;  ///< feeling: object vs model
};

// What the streamer keeps for the Model view between polls.
struct Session::ModelStream {
  CoverageTracker coverage;
  ObservedRecording observed;  ///< a bridged device's recording (Rig::observed)
  RunningRmse rmse;
  nlohmann::json points = nlohmann::json::array();  // [t, object xyz, model xyz] not yet sent
  double last_point_t = -1;
  std::chrono::steady_clock::time_point last_coverage{}, last_compare{};
  bool told_full = false;
};

}  // namespace inhap::studio
